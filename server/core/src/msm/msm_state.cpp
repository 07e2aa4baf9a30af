#include "hapsim/core/msm/msm_state.h"

#include <cstring>

namespace hapsim::core {

MsmState MakeMsmState(const MsmModel& model) {
  MsmState s;
  s.x_m = model.x0_m;
  s.v_m_per_s = Eigen::Matrix3Xd::Zero(3, model.num_nodes);
  s.f_ext_N = Eigen::Matrix3Xd::Zero(3, model.num_nodes);
  s.f_residual_N = Eigen::Matrix3Xd::Zero(3, model.num_nodes);
  return s;
}

namespace {
std::uint64_t Fnv1a(std::uint64_t h, const void* data, std::size_t bytes) {
  const auto* p = static_cast<const unsigned char*>(data);
  for (std::size_t k = 0; k < bytes; ++k) {
    h ^= p[k];
    h *= 1099511628211ull;
  }
  return h;
}
}  // namespace

std::uint64_t StateHash(const MsmState& s) {
  std::uint64_t h = 14695981039346656037ull;
  h = Fnv1a(h, &s.t_s, sizeof(s.t_s));
  h = Fnv1a(h, s.x_m.data(), sizeof(double) * static_cast<std::size_t>(s.x_m.size()));
  h = Fnv1a(h, s.v_m_per_s.data(), sizeof(double) * static_cast<std::size_t>(s.v_m_per_s.size()));
  return h;
}

}  // namespace hapsim::core
