#include "hapsim/core/haptics/local_force_model.h"

#include <cmath>

#include <gtest/gtest.h>

namespace hapsim::core {
namespace {

TEST(LocalForceModel, FreeGivesFeedforwardOnly) {
  LocalForceModel m;
  m.feedforward_W_N = {0.1, -0.2, 0.3};
  EXPECT_TRUE(EvaluateLocalForce(m, {1, 2, 3}, {4, 5, 6}).isApprox(m.feedforward_W_N));
}

TEST(LocalForceModel, ContactIsHookeanAlongNormal) {
  LocalForceModel m;
  m.state = ContactState::kContact;
  m.anchor_W_m = {0, 0, 0};
  m.normal_W = {0, 0, 1};
  m.stiffness_N_per_m = 200.0;
  // 2 mm below the surface, at rest: F = k * 0.002 = 0.4 N up.
  const Eigen::Vector3d f = EvaluateLocalForce(m, {0.01, 0, -0.002}, Eigen::Vector3d::Zero());
  EXPECT_NEAR(f.z(), 0.4, 1e-12);
  EXPECT_NEAR(f.head<2>().norm(), 0.0, 1e-12);
  // Above the surface: no force.
  EXPECT_NEAR(EvaluateLocalForce(m, {0, 0, 0.001}, Eigen::Vector3d::Zero()).norm(), 0.0, 1e-15);
}

TEST(LocalForceModel, ContactDamperNeverPullsTheToolIn) {
  LocalForceModel m;
  m.state = ContactState::kContact;
  m.stiffness_N_per_m = 100.0;
  m.damping_Ns_per_m = 10.0;
  // Withdrawing fast (v·n = +1 m/s) while 1 mm in: k p - b v = 0.1 - 10 < 0 -> 0.
  EXPECT_NEAR(EvaluateLocalForce(m, {0, 0, -0.001}, {0, 0, 1}).norm(), 0.0, 1e-15);
}

TEST(LocalForceModel, TunnelPullsTowardAxisAndDampsAxialMotion) {
  LocalForceModel m;
  m.state = ContactState::kPunctured;
  m.anchor_W_m = {0, 0, 0};
  m.normal_W = {0, 0, 1};
  m.stiffness_N_per_m = 500.0;
  m.damping_Ns_per_m = 2.0;
  const Eigen::Vector3d f = EvaluateLocalForce(m, {0.001, 0, -0.01}, {0, 0, -0.01});
  EXPECT_NEAR(f.x(), -0.5, 1e-12);   // -k * 1 mm lateral
  EXPECT_NEAR(f.y(), 0.0, 1e-12);
  EXPECT_NEAR(f.z(), 0.02, 1e-12);   // -b * v_axial = -2 * (-0.01)
}

// Stick-slip shaft friction: an axial spring to the stick point, clamped to
// the Coulomb level drag_N; nonzero with the needle still.
TEST(LocalForceModel, PuncturedShaftSticksBelowTheCoulombLevelAndSlipsAtIt) {
  LocalForceModel m;
  m.state = ContactState::kPunctured;
  m.normal_W = {0, 0, 1};  // out of the tissue
  m.stick_W_m = {0, 0, -0.01};
  m.stick_stiffness_N_per_m = 300.0;
  m.drag_N = 0.04;
  const Eigen::Vector3d still = Eigen::Vector3d::Zero();
  EXPECT_NEAR(EvaluateLocalForce(m, {0, 0, -0.01 + 5e-5}, still).z(), -300.0 * 5e-5, 1e-15);  // sticking
  EXPECT_NEAR(EvaluateLocalForce(m, {0, 0, -0.01 - 5e-5}, still).z(), 300.0 * 5e-5, 1e-15);
  EXPECT_NEAR(EvaluateLocalForce(m, {0, 0, -0.01 + 1e-3}, still).z(), -0.04, 1e-15);          // slipping
  EXPECT_NEAR(EvaluateLocalForce(m, {0, 0, -0.01 - 1e-3}, still).z(), 0.04, 1e-15);
  m.stick_stiffness_N_per_m = 0.0;  // the paper's law: no Coulomb part
  EXPECT_EQ(EvaluateLocalForce(m, {0, 0, -0.01 + 1e-3}, still).z(), 0.0);
}

// With the needle through one layer and its tip on the next, that layer is a
// half-space across the axis: it pushes out along the axis by its stiffness
// times how far the tip is past its surface, and never pulls.
TEST(LocalForceModel, PuncturedTipPressingTheNextLayerIsASpringAlongTheAxisThatNeverPulls) {
  LocalForceModel m;
  m.state = ContactState::kPunctured;
  m.normal_W = Eigen::Vector3d(1, 0, 1).normalized();  // out of the tissue, tilted
  m.tip_anchor_W_m = {0.0, 0.0, -0.01};
  m.tip_stiffness_N_per_m = 250.0;
  const Eigen::Vector3d still = Eigen::Vector3d::Zero();
  const Eigen::Vector3d deeper = m.tip_anchor_W_m - 2e-4 * m.normal_W;
  const Eigen::Vector3d f = EvaluateLocalForce(m, deeper, still);
  EXPECT_NEAR(f.dot(m.normal_W), 250.0 * 2e-4, 1e-15);
  EXPECT_NEAR((f - f.dot(m.normal_W) * m.normal_W).norm(), 0.0, 1e-15);  // along the axis only
  // Sideways on the surface's plane: the same depth, the same push.
  const Eigen::Vector3d across = Eigen::Vector3d(1, 0, -1).normalized();
  EXPECT_NEAR(EvaluateLocalForce(m, deeper + 1e-3 * across, still).dot(m.normal_W), 250.0 * 2e-4, 1e-15);
  EXPECT_EQ(EvaluateLocalForce(m, m.tip_anchor_W_m + 2e-4 * m.normal_W, still).norm(), 0.0);  // short of it
  m.tip_stiffness_N_per_m = 0.0;                                                              // the tip presses nothing
  EXPECT_EQ(EvaluateLocalForce(m, deeper, still).norm(), 0.0);
}

// A negative or NaN Coulomb level from the wire is no friction at all (not
// a crossed clamp, not a drag that pushes along the motion).
TEST(LocalForceModel, ANegativeOrNanCoulombLevelGivesNoFriction) {
  for (const double bad : {-0.5, std::nan("")}) {
    LocalForceModel m;
    m.state = ContactState::kPunctured;
    m.normal_W = {0, 0, 1};
    m.stick_stiffness_N_per_m = 300.0;
    m.drag_N = bad;
    EXPECT_EQ(EvaluateLocalForce(m, {0, 0, 1e-3}, Eigen::Vector3d::Zero()).z(), 0.0);
    m.state = ContactState::kCutting;
    m.anchor_W_m = {0, 0, -1};  // no penetration: only the drag could act
    m.drag_direction_W = {1, 0, 0};
    EXPECT_EQ(EvaluateLocalForce(m, {0, 0, 0}, {0.01, 0, 0}).x(), 0.0);
  }
}

}  // namespace
}  // namespace hapsim::core
