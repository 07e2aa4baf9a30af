#include "hapsim/core/msm/msm_state.h"

#include "hapsim/core/state_hash.h"

namespace hapsim::core {

MsmState MakeMsmState(const MsmModel& model) {
  MsmState s;
  s.x_m = model.x0_m;
  s.v_m_per_s = Eigen::Matrix3Xd::Zero(3, model.num_nodes);
  s.f_ext_N = Eigen::Matrix3Xd::Zero(3, model.num_nodes);
  s.f_residual_N = Eigen::Matrix3Xd::Zero(3, model.num_nodes);
  return s;
}

std::uint64_t StateHash(const MsmState& s) {
  return StateHasher().Add(s.t_s).Add(s.x_m).Add(s.v_m_per_s).Value();
}

}  // namespace hapsim::core
