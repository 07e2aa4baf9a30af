// Mutable MSM data: everything a step changes or the caller injects.
#pragma once
#include <cstdint>

#include <Eigen/Core>

#include "hapsim/core/msm/msm_model.h"

namespace hapsim::core {

struct MsmState {
  double t_s = 0.0;                // simulated time [s]
  Eigen::Matrix3Xd x_m;            // node positions [m] (3 x n)
  Eigen::Matrix3Xd v_m_per_s;      // node velocities [m/s] (3 x n)
  Eigen::Matrix3Xd f_ext_N;        // external force per node, held over a step [N] (3 x n)
  // Residual-stress force per node [N] (3 x n): set by cutting on wound-edge
  // nodes (sigma_r x the node's share of the cut face), zero otherwise.
  Eigen::Matrix3Xd f_residual_N;
  std::uint64_t blowups = 0;       // steps the stability guard rejected
};

// State at rest in the model's initial configuration.
MsmState MakeMsmState(const MsmModel& model);

// FNV-1a (StateHasher) over the exact bytes of t, x and v: equal hashes <=>
// bit-identical. Scenes hash more of the state (Scene::StateHash).
std::uint64_t StateHash(const MsmState& state);

}  // namespace hapsim::core
