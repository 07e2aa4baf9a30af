// MSM forces and energies, for callers outside the step (tests, tools,
// scenes reading the contact reaction). The step itself uses the same
// kernels (src/msm/msm_kernels.h), so what is tested here is what runs.
//
// Force on node i (SI):
//   f_i = f_ext_i + f_residual_i + m_i g - D_i v_i
//       + sum over springs (i,j): [k (l - L0) + c (v_j - v_i)·u] u,  u = (x_j - x_i)/l
//       + sum over anchors at i: -k_a (x_i - p_a) - c_a v_i
#pragma once
#include <Eigen/Core>

#include "hapsim/core/msm/msm_model.h"
#include "hapsim/core/msm/msm_state.h"

namespace hapsim::core {

// f = total force per node [N] (3 x n) at positions x, velocities v, with the
// external and residual forces held in state. f is resized (allocates).
void ComputeForces(const MsmModel& model, const MsmState& state, const Eigen::Matrix3Xd& x_m,
                   const Eigen::Matrix3Xd& v_m_per_s, Eigen::Matrix3Xd& f_N);

// Elastic energy of springs and anchors plus the potential of the constant
// forces (gravity, external, residual): f_conservative = -dE/dx [J].
double PotentialEnergy_J(const MsmModel& model, const MsmState& state, const Eigen::Matrix3Xd& x_m);
double KineticEnergy_J(const MsmModel& model, const Eigen::Matrix3Xd& v_m_per_s);

// K = -d(f_conservative)/dx, dense (3n x 3n), entry (3i+a, 3j+b). Exact
// Hessian of PotentialEnergy_J when clamp_compression is false. With
// clamp_compression the geometric term k (1 - L0/l) is clamped at >= 0 (what
// the implicit solver uses), which makes K positive semi-definite in every
// configuration. For tests and tools; allocates.
Eigen::MatrixXd AssembleStiffness(const MsmModel& model, const Eigen::Matrix3Xd& x_m,
                                  bool clamp_compression);

}  // namespace hapsim::core
