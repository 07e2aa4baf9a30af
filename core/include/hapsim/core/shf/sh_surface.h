// A closed surface as spherical harmonics (the acupuncture paper's eq. 3–5):
// each coordinate x, y, z of the surface point is Σ_{l<=Lmax} Σ_m c_lm Y_lm(θ,φ)
// in the real basis of real_spherical_harmonics.h.
#pragma once
#include <Eigen/Core>

#include "hapsim/core/shf/real_spherical_harmonics.h"

namespace hapsim::core {

struct ShSurface {
  int lmax = 0;
  // Column 0/1/2: coefficients of x/y/z [m], row j = l² + l + m ((Lmax+1)² x 3).
  Eigen::MatrixX3d coeffs_m;
};

// r̂ = Σ ĉ_lm Y_lm for basis values already evaluated at (θ,φ) (paper eq. 5).
inline Eigen::Vector3d ShSurfacePoint(const ShSurface& s, const Eigen::Ref<const Eigen::VectorXd>& basis) {
  return s.coeffs_m.transpose() * basis;
}

}  // namespace hapsim::core
