// SH surface fitting and the radial depth query: exactness where theory says
// exact, convergence with Lmax, and clear errors for under-sampled fits.
#include <cmath>
#include <numbers>
#include <string>

#include <gtest/gtest.h>

#include "hapsim/core/shf/layered_sh_body.h"
#include "hapsim/core/shf/limb_segment.h"
#include "hapsim/core/mesh/triangle_mesh.h"
#include "hapsim/core/shf/sh_fit.h"

namespace hapsim::core {
namespace {

constexpr double kA = 0.05, kB = 0.03, kC = 0.02;  // ellipsoid semi-axes [m]

// Ellipsoid in its natural parametrisation (a sinθcosφ, b sinθsinφ, c cosθ):
// each coordinate is a multiple of one l = 1 real harmonic.
void EllipsoidSamples(int n, Eigen::Matrix2Xd& tp, Eigen::Matrix3Xd& p) {
  const Eigen::Matrix3Xd u = FibonacciDirections(n);
  tp.resize(2, n);
  p.resize(3, n);
  for (int i = 0; i < n; ++i) {
    DirectionToAngles(u.col(i), tp(0, i), tp(1, i));
    p.col(i) << kA * u(0, i), kB * u(1, i), kC * u(2, i);
  }
}

double EllipsoidRadius(const Eigen::Vector3d& u) {
  const Eigen::Vector3d v = u.normalized();
  return 1.0 / std::sqrt(std::pow(v.x() / kA, 2) + std::pow(v.y() / kB, 2) + std::pow(v.z() / kC, 2));
}

TEST(ShFit, EllipsoidIsFittedExactlyByDegreeOneTerms) {
  Eigen::Matrix2Xd tp;
  Eigen::Matrix3Xd p;
  EllipsoidSamples(200, tp, p);
  const ShFitResult fit1 = FitShSurface(1, tp, p);
  EXPECT_LT(fit1.max_residual_m, 1e-15);
  // Analytic coefficients: x = a sinθcosφ = -a sqrt(4π/3) Y_{1,1} (Condon–Shortley sign).
  const double s = std::sqrt(4.0 * std::numbers::pi / 3.0);
  EXPECT_NEAR(fit1.surface.coeffs_m(RealShBasis::Index(1, 1), 0), -kA * s, 1e-15);
  EXPECT_NEAR(fit1.surface.coeffs_m(RealShBasis::Index(1, -1), 1), -kB * s, 1e-15);
  EXPECT_NEAR(fit1.surface.coeffs_m(RealShBasis::Index(1, 0), 2), kC * s, 1e-15);
  // A higher Lmax finds nothing more: every l >= 2 coefficient vanishes.
  const ShFitResult fit4 = FitShSurface(4, tp, p);
  EXPECT_LT(fit4.surface.coeffs_m.bottomRows(25 - 4).cwiseAbs().maxCoeff(), 1e-15);
}

TEST(ShFit, ResidualFallsAsLmaxGrowsForLimbSegment) {
  const LimbSegmentDef limb;
  const Eigen::Matrix3Xd p = SampleLimbSegment_m(limb, 1500);
  const Eigen::Matrix2Xd tp = RadialAngles(p, Eigen::Vector3d::Zero());
  double previous = std::numeric_limits<double>::infinity();
  for (int lmax : {2, 4, 8, 12, 16}) {
    const double rms = FitShSurface(lmax, tp, p).rms_residual_m;
    EXPECT_LT(rms, 0.8 * previous) << "Lmax " << lmax;
    previous = rms;
  }
  EXPECT_LT(previous, 1e-3);  // < 1 mm on a 0.4 m long segment at Lmax = 16
}

TEST(ShFit, TooFewSamplesIsAnErrorThatSaysHowMany) {
  Eigen::Matrix2Xd tp;
  Eigen::Matrix3Xd p;
  EllipsoidSamples(20, tp, p);
  try {
    FitShSurface(4, tp, p);  // k = 25 > 20
    FAIL() << "expected std::invalid_argument";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("need at least k = (Lmax+1)^2 = 25, got 20"), std::string::npos) << e.what();
  }
}

TEST(ShFit, SamplesOnOneSmallCapAreReportedIllConditioned) {
  // 400 samples, all within 10° of the north pole: enough rows, no coverage.
  Eigen::Matrix2Xd tp(2, 400);
  Eigen::Matrix3Xd p(3, 400);
  for (int i = 0; i < 400; ++i) {
    tp(0, i) = 0.17 * (i % 20 + 0.5) / 20;
    tp(1, i) = 2 * std::numbers::pi * (i / 20) / 20.0;
    p.col(i) = AnglesToDirection(tp(0, i), tp(1, i));
  }
  try {
    FitShSurface(6, tp, p);
    FAIL() << "expected std::invalid_argument";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("ill-conditioned"), std::string::npos) << e.what();
  }
}

TEST(RadialDepthQuery, SphereDepthIsRadiusMinusDistanceExactly) {
  const double r = 0.04;
  const Eigen::Matrix3Xd p = r * FibonacciDirections(100);
  LayeredShBodyDef def;
  def.center_W_m = Eigen::Vector3d(0.1, -0.2, 0.3);
  def.surfaces.push_back(FitShSurface(3, RadialAngles(p, Eigen::Vector3d::Zero()), p).surface);
  LayeredShBody body(def);
  Eigen::VectorXd depth(1);
  for (const Eigen::Vector3d& q : {Eigen::Vector3d(0.01, 0.0, 0.0), Eigen::Vector3d(0.0, 0.03, 0.02),
                                  Eigen::Vector3d(0.05, -0.05, 0.0)}) {
    body.Depths_m(def.center_W_m + q, depth);
    EXPECT_NEAR(depth[0], r - q.norm(), 1e-14);
  }
}

TEST(RadialDepthQuery, RadiallyFittedEllipsoidMatchesAnalyticRadius) {
  // Radial parametrisation of an ellipsoid is smooth but not band-limited:
  // at Lmax = 14 the radius error must be far below the 0.8 mm skin layer
  // (0.1 mm tolerance; a 5:3:2 ellipsoid is a harder shape than the limb).
  const Eigen::Matrix3Xd u = FibonacciDirections(1200);
  Eigen::Matrix3Xd p(3, u.cols());
  for (int i = 0; i < u.cols(); ++i) p.col(i) = EllipsoidRadius(u.col(i)) * u.col(i);
  LayeredShBodyDef def;
  def.surfaces.push_back(FitShSurface(14, RadialAngles(p, Eigen::Vector3d::Zero()), p).surface);
  LayeredShBody body(def);
  const Eigen::Matrix3Xd probe = FibonacciDirections(97);  // not the sample directions
  double worst = 0.0;
  for (int i = 0; i < probe.cols(); ++i)
    worst = std::max(worst, std::abs(body.Radius_m(0, probe.col(i)) - EllipsoidRadius(probe.col(i))));
  EXPECT_LT(worst, 1e-4);
  // Outward normal of the top of the ellipsoid (0,0,c) is +z.
  EXPECT_NEAR(body.OutwardNormal_W(0, Eigen::Vector3d(0, 0, 1)).z(), 1.0, 1e-6);
}

// A star-shaped test surface r(u) = 0.05 + 0.01 u_x u_y on a latitude-
// longitude grid, quads split in two (the same triangles hapsim::io's OBJ
// reader makes of the tests/io copy of this mesh).
TriangleMesh StarMesh(int nt, int np) {
  TriangleMesh mesh;
  mesh.vertices_m.resize(3, (nt + 1) * np);
  for (int i = 0; i <= nt; ++i)
    for (int j = 0; j < np; ++j) {
      const double th = std::numbers::pi * i / nt, ph = 2 * std::numbers::pi * j / np;
      const Eigen::Vector3d u = AnglesToDirection(th, ph);
      mesh.vertices_m.col(i * np + j) = (0.05 + 0.01 * u.x() * u.y()) * u;
    }
  for (int i = 0; i < nt; ++i)
    for (int j = 0; j < np; ++j) {
      const int a = i * np + j, b = i * np + (j + 1) % np;
      mesh.triangles.push_back({a, a + np, b + np});
      mesh.triangles.push_back({a, b + np, b});
    }
  return mesh;
}

TEST(TriangleMesh, StarShapedMeshIsCheckedAndFittedExactly) {
  const TriangleMesh mesh = StarMesh(12, 24);
  EXPECT_TRUE(IsStarShapedAbout(mesh, Eigen::Vector3d::Zero()));
  EXPECT_FALSE(IsStarShapedAbout(mesh, Eigen::Vector3d(0.2, 0.0, 0.0)));  // centre outside
  EXPECT_FALSE(IsStarShapedAbout(TriangleMesh{}, Eigen::Vector3d::Zero()));
  const ShFitResult fit = FitShSurface(4, RadialAngles(mesh.vertices_m, Eigen::Vector3d::Zero()), mesh.vertices_m);
  // 0.05 + 0.01 xy is degree 2 in u, times u: degree 3 <= Lmax, so the fit
  // is exact up to round-off.
  EXPECT_LT(fit.max_residual_m, 1e-12);
}

}  // namespace
}  // namespace hapsim::core
