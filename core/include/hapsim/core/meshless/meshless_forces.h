// Elastic forces of the meshless model (Müller et al. 2004 §4, with the
// Green strain's ½ — see below) and one explicit step. No allocation: the
// caller sizes MeshlessState once (MakeMeshlessState).
//
// At node i, with current positions x:
//   F_i = sum_j (x_j - x_i) d_ij^T            deformation gradient (= I + H_i;
//                                             sum_j x0_ij d_ij^T = A_i A_i^-1 = I)
//   E_i = ½ (F_i^T F_i - I)                   Green strain
//   S_i = lambda tr(E_i) I + 2 mu E_i         isotropic linear stress (St. Venant-Kirchhoff)
//   U_i = v_i ½ E_i : S_i                     strain energy [J]
//   f_j -= v_i F_i S_i d_ij  (each neighbour), f_i += v_i F_i S_i sum_j d_ij
// i.e. f = -dU/dx exactly, so the forces sum to zero and a rigid motion gives
// zero energy and zero force. Departure from the paper: Müller et al. write
// the strain as J^T J - I without the ½; with a linear stress that doubles
// the stiffness (a uniaxial test would measure 2E), so we keep the Green
// strain's ½ and E means Young's modulus.
#pragma once
#include <vector>

#include <Eigen/Core>

#include "hapsim/core/meshless/meshless_model.h"

namespace hapsim::core {

struct MeshlessState {
  Eigen::Matrix3Xd x_m, v_m_per_s, f_ext_N;  // (3 x n)
  Eigen::Matrix3Xd forces_N;                 // scratch: elastic forces of the last evaluation
  std::vector<Eigen::Matrix3d> F;            // (n) deformation gradients of the last evaluation
  double strain_energy_J = 0.0;
  double time_s = 0.0;
};

MeshlessState MakeMeshlessState(const MeshlessModel& model);  // at rest

// F_i for every node from positions x (3 x n) into F (sized n).
void ComputeDeformationGradients(const MeshlessModel& model, const Eigen::Matrix3Xd& x_m,
                                 std::vector<Eigen::Matrix3d>& F);

// Elastic forces (3 x n, overwritten) at positions x; returns the total strain
// energy [J]. F is scratch (sized n).
double ComputeMeshlessForces(const MeshlessModel& model, const Eigen::Matrix3Xd& x_m,
                             std::vector<Eigen::Matrix3d>& F, Eigen::Matrix3Xd& forces_N);

// One symplectic-Euler step of h seconds: v += h (f_elastic + f_ext) / m - h c v,
// x += h v; fixed nodes keep their position and zero velocity. Explicit:
// stable below ~ the time for a wave to cross the node spacing
// (h < s / sqrt((lambda + 2 mu) / rho)).
void StepMeshless(const MeshlessModel& model, MeshlessState& state, double h_s);

}  // namespace hapsim::core
