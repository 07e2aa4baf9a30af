// Shape matching springback: robust rotation extraction and the paper's
// damped goals with η in [0, 1].
#include <cmath>
#include <random>

#include <Eigen/Geometry>
#include <gtest/gtest.h>

#include "hapsim/core/shape_matching/shape_matching.h"

namespace hapsim::core {
namespace {

bool IsProperRotation(const Eigen::Matrix3d& R) {
  return (R * R.transpose()).isIdentity(1e-12) && std::abs(R.determinant() - 1.0) < 1e-12;
}

TEST(ExtractRotation, RecoversKnownRotationOfARotatedShape) {
  const Eigen::Matrix3d R0 = Eigen::AngleAxisd(0.7, Eigen::Vector3d(1, 2, 3).normalized()).toRotationMatrix();
  std::mt19937 rng(1);
  std::normal_distribution<double> g;
  Eigen::Matrix3d A = Eigen::Matrix3d::Zero();
  for (int i = 0; i < 20; ++i) {
    const Eigen::Vector3d q(g(rng), g(rng), g(rng));
    A += (R0 * q) * q.transpose();  // A = R0 Σ q qᵀ: polar factor is R0
  }
  EXPECT_LT((ExtractRotation(A) - R0).cwiseAbs().maxCoeff(), 1e-12);
}

TEST(ExtractRotation, NeverReturnsAReflection) {
  // det A < 0: an inverted element. (AᵀA)^(-1/2) would give a reflection.
  const Eigen::Matrix3d A = Eigen::Vector3d(2.0, 1.0, -0.5).asDiagonal();
  const Eigen::Matrix3d R = ExtractRotation(A);
  EXPECT_TRUE(IsProperRotation(R));
  // Closest rotation flips the axis of the smallest singular value only.
  EXPECT_LT((R - Eigen::Matrix3d::Identity()).cwiseAbs().maxCoeff(), 1e-12);
}

TEST(ExtractRotation, FlatRestShapeIsHandled) {
  // Coplanar rest points make A rank 2 (AᵀA singular); the SVD route still
  // returns the rotation that maps the plane.
  const Eigen::Matrix3d R0 = Eigen::AngleAxisd(-0.4, Eigen::Vector3d(0.3, -1, 0.2).normalized()).toRotationMatrix();
  Eigen::Matrix3d A = Eigen::Matrix3d::Zero();
  for (int i = 0; i < 6; ++i) {
    const Eigen::Vector3d q(std::cos(i), std::sin(i), 0.0);
    A += (R0 * q) * q.transpose();
  }
  const Eigen::Matrix3d R = ExtractRotation(A);
  EXPECT_TRUE(IsProperRotation(R));
  EXPECT_LT((R - R0).cwiseAbs().maxCoeff(), 1e-12);
}

struct Dimple {
  Eigen::Matrix3Xd rest, x;
  Eigen::VectorXd mass, eta;
};

Dimple MakeDimple(int n, double depth_m) {
  Dimple d;
  d.rest.resize(3, n);
  d.x.resize(3, n);
  for (int i = 0; i < n; ++i) {
    const double r = 1e-3 * i / std::sqrt(n);
    d.rest.col(i) << r * std::cos(2.4 * i), r * std::sin(2.4 * i), 0.0;
    d.x.col(i) = d.rest.col(i) - Eigen::Vector3d(0, 0, depth_m * std::exp(-r / 2e-3));
  }
  d.mass = Eigen::VectorXd::Ones(n);
  d.eta = Eigen::VectorXd::Ones(n);
  return d;
}

TEST(Springback, EtaStaysInUnitIntervalAndReachesZero) {
  Dimple d = MakeDimple(40, 1e-3);
  double previous = 1.0;
  for (int step = 0; step < 100; ++step) {
    SpringbackStep(d.rest, d.mass, 0.013, d.x, d.eta);
    EXPECT_GE(d.eta.minCoeff(), 0.0);
    EXPECT_LE(d.eta.maxCoeff(), 1.0);
    EXPECT_LE(d.eta[0], previous);
    previous = d.eta[0];
  }
  EXPECT_EQ(d.eta.maxCoeff(), 0.0);
}

TEST(Springback, EtaOneHoldsAndEtaZeroJumpsToRigidGoal) {
  Dimple d = MakeDimple(30, 1e-3);
  const Eigen::Matrix3Xd before = d.x;
  SpringbackStep(d.rest, d.mass, 0.0, d.x, d.eta);  // η = 1 stays 1
  EXPECT_LT((d.x - before).cwiseAbs().maxCoeff(), 1e-18);
  d.eta.setZero();
  SpringbackStep(d.rest, d.mass, 0.0, d.x, d.eta);
  // At the goal the shape is the rest shape moved rigidly: distances kept.
  for (int i = 1; i < 30; ++i)
    EXPECT_NEAR((d.x.col(i) - d.x.col(0)).norm(), (d.rest.col(i) - d.rest.col(0)).norm(), 1e-15);
}

TEST(Springback, DimpleRisesToMeanDeflectionAboveTheTipReference) {
  // A symmetric-enough dimple has R = I, so the end state is the rest shape
  // lowered by the mean deflection: the deepest point ends above where it was.
  Dimple d = MakeDimple(60, 1e-3);
  const double mean_z = d.x.row(2).mean();
  const double tip_reference_z = d.x(2, 0);
  for (int step = 0; step < 200; ++step) SpringbackStep(d.rest, d.mass, 0.02, d.x, d.eta);
  EXPECT_GT(d.x(2, 0), tip_reference_z);
  EXPECT_NEAR(d.x.row(2).mean(), mean_z, 1e-15);  // the centroid never moves
  EXPECT_LT((d.x.row(2).array() - mean_z).abs().maxCoeff(), 2e-5);  // flat again (tilt from asymmetry only)
}

}  // namespace
}  // namespace hapsim::core
