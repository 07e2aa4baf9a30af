#include "hapsim/core/shf/real_spherical_harmonics.h"

#include <cmath>
#include <numbers>
#include <stdexcept>
#include <string>

#include "hapsim/core/math/portable_math.h"

namespace hapsim::core {

RealShBasis::RealShBasis(int lmax) : lmax_(lmax) {
  if (lmax < 0 || lmax > 200)
    throw std::invalid_argument("RealShBasis: lmax must be in [0, 200], got " + std::to_string(lmax));
  const int n = lmax + 1;
  a_lm_.assign(static_cast<std::size_t>(n * n), 0.0);
  b_lm_.assign(static_cast<std::size_t>(n * n), 0.0);
  diag_.assign(static_cast<std::size_t>(n), 0.0);
  subdiag_.assign(static_cast<std::size_t>(n), 0.0);
  for (int m = 0; m <= lmax; ++m) {
    if (m >= 1) diag_[static_cast<std::size_t>(m)] = -std::sqrt((2.0 * m + 1.0) / (2.0 * m));
    subdiag_[static_cast<std::size_t>(m)] = std::sqrt(2.0 * m + 3.0);
    for (int l = m + 2; l <= lmax; ++l) {
      const double l2 = double(l) * l, m2 = double(m) * m, lm1 = l - 1.0;
      const std::size_t i = static_cast<std::size_t>(l * n + m);
      a_lm_[i] = std::sqrt((4.0 * l2 - 1.0) / (l2 - m2));
      b_lm_[i] = std::sqrt((lm1 * lm1 - m2) / (4.0 * lm1 * lm1 - 1.0));
    }
  }
}

void RealShBasis::Evaluate(double theta_rad, double phi_rad, Eigen::Ref<Eigen::VectorXd> out) const {
  double st = 0, ct = 0, sp = 0, cp = 0;
  pmath::SinCos(theta_rad, st, ct);
  pmath::SinCos(phi_rad, sp, cp);
  EvaluateTrig(ct, st, cp, sp, out);
}

void RealShBasis::EvaluateDirection(const Eigen::Vector3d& u, Eigen::Ref<Eigen::VectorXd> out) const {
  const double r = u.norm();
  const double rho = pmath::Hypot(u.x(), u.y());
  // On the polar axis phi is arbitrary; every m > 0 term carries sin^m(theta) = 0.
  const double cp = rho > 0.0 ? u.x() / rho : 1.0;
  const double sp = rho > 0.0 ? u.y() / rho : 0.0;
  EvaluateTrig(u.z() / r, rho / r, cp, sp, out);
}

void RealShBasis::EvaluateTrig(double ct, double st, double cp, double sp,
                               Eigen::Ref<Eigen::VectorXd> out) const {
  const int n = lmax_ + 1;
  const double sqrt2 = std::numbers::sqrt2;
  double pmm = 0.5 / std::sqrt(std::numbers::pi);  // normalised P_0^0
  double cos_m = 1.0, sin_m = 0.0;                 // pmath::Cos(m phi), pmath::Sin(m phi)
  for (int m = 0; m <= lmax_; ++m) {
    if (m >= 1) {
      pmm *= diag_[static_cast<std::size_t>(m)] * st;
      const double c = cos_m * cp - sin_m * sp;
      sin_m = sin_m * cp + cos_m * sp;
      cos_m = c;
    }
    const double wc = m == 0 ? 1.0 : sqrt2 * cos_m;
    const double ws = sqrt2 * sin_m;
    // l = m
    double p_lm2 = 0.0, p_lm1 = pmm;
    out[Index(m, m)] = wc * pmm;
    if (m > 0) out[Index(m, -m)] = ws * pmm;
    if (m + 1 <= lmax_) {
      const double p = subdiag_[static_cast<std::size_t>(m)] * ct * pmm;
      out[Index(m + 1, m)] = wc * p;
      if (m > 0) out[Index(m + 1, -m)] = ws * p;
      p_lm2 = pmm;
      p_lm1 = p;
    }
    for (int l = m + 2; l <= lmax_; ++l) {
      const std::size_t i = static_cast<std::size_t>(l * n + m);
      const double p = a_lm_[i] * (ct * p_lm1 - b_lm_[i] * p_lm2);
      out[Index(l, m)] = wc * p;
      if (m > 0) out[Index(l, -m)] = ws * p;
      p_lm2 = p_lm1;
      p_lm1 = p;
    }
  }
}

void DirectionToAngles(const Eigen::Vector3d& u, double& theta_rad, double& phi_rad) {
  theta_rad = pmath::Atan2(pmath::Hypot(u.x(), u.y()), u.z());
  phi_rad = pmath::Atan2(u.y(), u.x());
}

Eigen::Vector3d AnglesToDirection(double theta_rad, double phi_rad) {
  return {pmath::Sin(theta_rad) * pmath::Cos(phi_rad), pmath::Sin(theta_rad) * pmath::Sin(phi_rad),
          pmath::Cos(theta_rad)};
}

}  // namespace hapsim::core
