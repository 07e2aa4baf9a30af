// Least-squares fit of SH surface coefficients from sampled surface points
// (the acupuncture paper's eq. 4): for n samples with parameters (θ_i, φ_i)
// and positions p_i, build Y (n x k), Y_ij = Y_j(θ_i, φ_i), and solve
// Y c ≈ p for x, y and z.
//
// Parametrisation [decide]: a sampled surface has no (θ,φ) of
// its own; for star-shaped layers we use the radial projection from a centre
// (RadialAngles): θ,φ = angles of p - c. That makes x̂(u) - c ≈ r(u)·u, which
// is what the radial depth query needs. Surfaces with a natural
// parametrisation (an ellipsoid's a sinθcosφ, ...) can be fitted with it.
#pragma once
#include <string>

#include <Eigen/Core>

#include "hapsim/core/shf/sh_surface.h"

namespace hapsim::core {

struct ShFitResult {
  ShSurface surface;
  double condition_number = 0.0;  // σ_max / σ_min of Y (2-norm)
  double rms_residual_m = 0.0;    // RMS of |x̂(θ_i,φ_i) - p_i| over the samples
  double max_residual_m = 0.0;
};

// Throws std::invalid_argument, saying what to change, when there are fewer
// samples than the k = (Lmax+1)² unknowns, when sizes disagree, or when Y is
// ill-conditioned (condition number above max_condition_number: samples
// clustered or too sparse for this Lmax).
ShFitResult FitShSurface(int lmax, const Eigen::Matrix2Xd& theta_phi_rad, const Eigen::Matrix3Xd& points_m,
                         double max_condition_number = 1e10);

// (θ, φ) of each p_i - center (radial projection). Throws if a point is at the centre.
Eigen::Matrix2Xd RadialAngles(const Eigen::Matrix3Xd& points_m, const Eigen::Vector3d& center_m);

// n nearly uniform unit directions (Fibonacci sphere), deterministic (3 x n).
Eigen::Matrix3Xd FibonacciDirections(int n);

}  // namespace hapsim::core
