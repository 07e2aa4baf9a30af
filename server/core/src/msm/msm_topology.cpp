#include "hapsim/core/msm/msm_topology.h"

#include <cmath>
#include <stdexcept>
#include <string>

namespace hapsim::core {

std::int32_t FindSpring(const MsmModel& m, std::int32_t a, std::int32_t b) {
  for (std::int32_t s = 0; s < m.NumSprings(); ++s) {
    if ((m.spring_i[s] == a && m.spring_j[s] == b) || (m.spring_i[s] == b && m.spring_j[s] == a))
      return s;
  }
  return -1;
}

void RemoveSpring(MsmModel& m, std::int32_t s) {
  if (s < 0 || s >= m.NumSprings())
    throw std::out_of_range("RemoveSpring: spring " + std::to_string(s) + " not in [0, " +
                            std::to_string(m.NumSprings()) + ")");
  const auto last = static_cast<std::size_t>(m.NumSprings() - 1);
  const auto k = static_cast<std::size_t>(s);
  m.spring_i[k] = m.spring_i[last];
  m.spring_j[k] = m.spring_j[last];
  m.spring_rest_m[k] = m.spring_rest_m[last];
  m.spring_k_N_per_m[k] = m.spring_k_N_per_m[last];
  m.spring_c_Ns_per_m[k] = m.spring_c_Ns_per_m[last];
  m.spring_i.pop_back();
  m.spring_j.pop_back();
  m.spring_rest_m.pop_back();
  m.spring_k_N_per_m.pop_back();
  m.spring_c_Ns_per_m.pop_back();
}

std::int32_t AddSpring(MsmModel& m, std::int32_t i, std::int32_t j, double rest_m, double k_N_per_m,
                       double c_Ns_per_m) {
  if (i < 0 || j < 0 || i >= m.num_nodes || j >= m.num_nodes || i == j)
    throw std::invalid_argument("AddSpring: nodes (" + std::to_string(i) + ", " + std::to_string(j) +
                                ") must be distinct and in [0, " + std::to_string(m.num_nodes) + ")");
  if (!(std::isfinite(rest_m) && rest_m >= 0 && std::isfinite(k_N_per_m) && k_N_per_m >= 0 &&
        std::isfinite(c_Ns_per_m) && c_Ns_per_m >= 0))
    throw std::invalid_argument("AddSpring: rest length, stiffness and damping must be finite and >= 0");
  if (m.NumSprings() >= m.spring_capacity)
    throw std::length_error("AddSpring: spring_capacity " + std::to_string(m.spring_capacity) +
                            " reached; build the model with a larger MsmDef::spring_capacity");
  m.spring_i.push_back(i);  // within reserved capacity: no reallocation
  m.spring_j.push_back(j);
  m.spring_rest_m.push_back(rest_m);
  m.spring_k_N_per_m.push_back(k_N_per_m);
  m.spring_c_Ns_per_m.push_back(c_Ns_per_m);
  return m.NumSprings() - 1;
}

void SetResidualForce(MsmState& state, std::int32_t node, const Eigen::Vector3d& f_N) {
  if (node < 0 || node >= state.f_residual_N.cols())
    throw std::out_of_range("SetResidualForce: node " + std::to_string(node) + " out of range");
  state.f_residual_N.col(node) = f_N;
}

}  // namespace hapsim::core
