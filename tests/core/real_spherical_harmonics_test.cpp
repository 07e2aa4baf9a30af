// Real SH basis: values against std::sph_legendre (an independent
// implementation that includes the normalisation and the Condon–Shortley
// phase), orthonormality by quadrature, and no overflow at high degree.
#include <cmath>
#include <numbers>
#include <random>

#include <gtest/gtest.h>

#include "hapsim/core/shf/real_spherical_harmonics.h"

namespace hapsim::core {
namespace {

// Reference real SH built from std::sph_legendre (C++17 special functions).
double ReferenceRealSh(int l, int m, double theta, double phi) {
  const int am = std::abs(m);
  const double p = std::sph_legendre(static_cast<unsigned>(l), static_cast<unsigned>(am), theta);
  if (m == 0) return p;
  return std::numbers::sqrt2 * p * (m > 0 ? std::cos(am * phi) : std::sin(am * phi));
}

TEST(RealSphericalHarmonics, MatchesStdSphLegendreAtRandomPointsTo1e12) {
  constexpr int kLmax = 30;
  const RealShBasis basis(kLmax);
  Eigen::VectorXd y(basis.Size());
  std::mt19937 rng(42);
  std::uniform_real_distribution<double> th(0.0, std::numbers::pi), ph(-std::numbers::pi, std::numbers::pi);
  double worst = 0.0;
  for (int trial = 0; trial < 200; ++trial) {
    const double theta = th(rng), phi = ph(rng);
    basis.Evaluate(theta, phi, y);
    for (int l = 0; l <= kLmax; ++l)
      for (int m = -l; m <= l; ++m)
        worst = std::max(worst, std::abs(y[RealShBasis::Index(l, m)] - ReferenceRealSh(l, m, theta, phi)));
  }
  EXPECT_LT(worst, 1e-12);
}

TEST(RealSphericalHarmonics, PhaseConventionIncludesCondonShortley) {
  // Y_{1,1} = -sqrt(3/(4π)) sinθ cosφ with the (-1)^m phase (the classic
  // pitfall: without it the sign flips).
  const RealShBasis basis(1);
  Eigen::VectorXd y(basis.Size());
  basis.Evaluate(std::numbers::pi / 2, 0.0, y);
  EXPECT_NEAR(y[RealShBasis::Index(1, 1)], -std::sqrt(3.0 / (4.0 * std::numbers::pi)), 1e-15);
  EXPECT_NEAR(y[RealShBasis::Index(1, 0)], 0.0, 1e-15);
}

TEST(RealSphericalHarmonics, DirectionAndAngleEvaluationAgree) {
  const RealShBasis basis(12);
  Eigen::VectorXd a(basis.Size()), b(basis.Size());
  std::mt19937 rng(7);
  std::normal_distribution<double> g;
  for (int i = 0; i < 50; ++i) {
    const Eigen::Vector3d u(g(rng), g(rng), g(rng));
    double theta = 0, phi = 0;
    DirectionToAngles(u, theta, phi);
    basis.Evaluate(theta, phi, a);
    basis.EvaluateDirection(3.7 * u, b);  // length must not matter
    EXPECT_LT((a - b).cwiseAbs().maxCoeff(), 1e-13);
  }
  // On the pole every m != 0 term vanishes.
  basis.EvaluateDirection(Eigen::Vector3d::UnitZ(), b);
  basis.Evaluate(0.0, 0.0, a);
  EXPECT_LT((a - b).cwiseAbs().maxCoeff(), 1e-14);
}

TEST(RealSphericalHarmonics, OrthonormalUnderGaussLegendreQuadrature) {
  // Exact quadrature for band-limited products: Gauss–Legendre in cos θ
  // (N nodes) x uniform φ (2N points) integrates degree < 2N exactly.
  constexpr int kLmax = 8, kN = 12;
  const RealShBasis basis(kLmax);
  // Gauss–Legendre nodes by Newton on P_N (independent of the SH code).
  std::vector<double> x(kN), w(kN);
  for (int i = 0; i < kN; ++i) {
    double z = std::cos(std::numbers::pi * (i + 0.75) / (kN + 0.5)), dp = 0;
    for (int it = 0; it < 100; ++it) {
      double p0 = 1, p1 = z;
      for (int k = 2; k <= kN; ++k) {
        const double p2 = ((2.0 * k - 1) * z * p1 - (k - 1.0) * p0) / k;
        p0 = p1;
        p1 = p2;
      }
      dp = kN * (z * p1 - p0) / (z * z - 1);
      z -= p1 / dp;
    }
    x[i] = z;
    w[i] = 2 / ((1 - z * z) * dp * dp);
  }
  const int k = basis.Size();
  Eigen::MatrixXd gram = Eigen::MatrixXd::Zero(k, k);
  Eigen::VectorXd y(k);
  for (int i = 0; i < kN; ++i)
    for (int j = 0; j < 2 * kN; ++j) {
      basis.Evaluate(std::acos(x[i]), 2 * std::numbers::pi * j / (2 * kN), y);
      gram += w[i] * (2 * std::numbers::pi / (2 * kN)) * y * y.transpose();
    }
  EXPECT_LT((gram - Eigen::MatrixXd::Identity(k, k)).cwiseAbs().maxCoeff(), 1e-12);
}

TEST(RealSphericalHarmonics, NoOverflowAtHighDegree) {
  const RealShBasis basis(60);
  Eigen::VectorXd y(basis.Size());
  basis.Evaluate(0.3, 1.1, y);
  EXPECT_TRUE(y.allFinite());
  // Each |Y_lm| <= sqrt((2l+1)/(4π)) · √2 (addition theorem bound).
  for (int l = 0; l <= 60; ++l)
    for (int m = -l; m <= l; ++m)
      EXPECT_LE(std::abs(y[RealShBasis::Index(l, m)]), std::sqrt((2.0 * l + 1) / (4 * std::numbers::pi)) * 1.5);
}

TEST(RealSphericalHarmonics, RejectsNegativeDegree) { EXPECT_THROW(RealShBasis(-1), std::invalid_argument); }

}  // namespace
}  // namespace hapsim::core
