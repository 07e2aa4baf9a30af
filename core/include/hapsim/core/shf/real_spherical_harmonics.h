// Real spherical-harmonic (SH) basis up to any degree Lmax.
//
// Convention (pinned by tests against std::sph_legendre and scipy):
//   Y_{l,0}  = N_l^0 P_l^0(cos θ)
//   Y_{l,m}  = √2 N_l^m P_l^m(cos θ) cos(m φ)      m > 0
//   Y_{l,-m} = √2 N_l^m P_l^m(cos θ) sin(m φ)      m > 0
// where N_l^m P_l^m = std::sph_legendre(l, m, θ), i.e. orthonormal on the
// unit sphere and *including* the Condon–Shortley phase (-1)^m. Spans the
// same space as the acupuncture paper's complex Y_l^m, no complex maths.
// Column index (0-based) j = l² + l + m, k = (Lmax + 1)² columns.
//
// Values come from the stable three-term recurrence of the normalised
// associated Legendre functions (no factorials, so no overflow at Lmax = 30
// and far beyond); cos/sin(mφ) by the angle-addition recurrence.
#pragma once
#include <Eigen/Core>
#include <vector>

namespace hapsim::core {

class RealShBasis {
 public:
  // Throws std::invalid_argument unless 0 <= lmax <= 200.
  explicit RealShBasis(int lmax);

  int Lmax() const { return lmax_; }
  int Size() const { return (lmax_ + 1) * (lmax_ + 1); }  // k
  static int Index(int l, int m) { return l * l + l + m; }

  // All k basis values at polar angle theta_rad (from +z) and azimuth phi_rad
  // (from +x towards +y). out must have Size() entries. Never allocates.
  void Evaluate(double theta_rad, double phi_rad, Eigen::Ref<Eigen::VectorXd> out) const;
  // Same at the direction of u (any non-zero length; no trigonometry).
  void EvaluateDirection(const Eigen::Vector3d& u, Eigen::Ref<Eigen::VectorXd> out) const;

 private:
  void EvaluateTrig(double cos_theta, double sin_theta, double cos_phi, double sin_phi,
                    Eigen::Ref<Eigen::VectorXd> out) const;

  int lmax_;
  // Recurrence coefficients, precomputed (sizes (lmax+1)^2, indexed l(l+1)/2+m
  // style would save memory; the square layout keeps indexing obvious).
  std::vector<double> a_lm_;    // sqrt((4l²-1)/(l²-m²))
  std::vector<double> b_lm_;    // sqrt(((l-1)²-m²)/(4(l-1)²-1))
  std::vector<double> diag_;    // -sqrt((2m+1)/(2m)), m >= 1
  std::vector<double> subdiag_; // sqrt(2m+3)
};

// Polar/azimuth angles of a direction (any non-zero length) [rad].
void DirectionToAngles(const Eigen::Vector3d& u, double& theta_rad, double& phi_rad);
Eigen::Vector3d AnglesToDirection(double theta_rad, double phi_rad);

}  // namespace hapsim::core
