// Shape matching (Müller et al. 2005) with the acupuncture paper's damped
// goals (§3.3, eqs. 7–9), used for the springback of a punctured surface.
//   A   = Σ M_i (p_i - p_cm)(p0_i - p0_cm)ᵀ
//   R   = rotation of the polar decomposition of A
//   g_i = R (p0_i - p0_cm) + p_cm
//   g_i ← g_i + η_i (p_i - g_i);  p_i ← g_i;  η_i ← max(0, η_i - η_r)
// η = 1: the particle stays; η = 0: it jumps to its goal.
#pragma once
#include <Eigen/Core>

namespace hapsim::core {

// Rotation part of the polar decomposition A = R S, robust for every A:
// from the SVD A = U Σ Vᵀ, R = U diag(1, 1, det(U Vᵀ)) Vᵀ. The sign fix
// keeps R a proper rotation (det = +1) when det A < 0 (a reflection, where
// R = A (AᵀA)^(-1/2) would return one) and when A is rank-deficient (e.g. a
// flat rest shape, where AᵀA is singular). Never allocates.
Eigen::Matrix3d ExtractRotation(const Eigen::Matrix3d& A);

// One damped springback step on positions x_m (3 x n) towards the rest shape
// rest_m (3 x n) with masses mass (n) and per-particle factors eta (n) in
// [0, 1]; eta decreases by eta_rate_per_step and is clamped at 0. Never allocates.
void SpringbackStep(const Eigen::Matrix3Xd& rest_m, const Eigen::VectorXd& mass, double eta_rate_per_step,
                    Eigen::Matrix3Xd& x_m, Eigen::VectorXd& eta);

}  // namespace hapsim::core
