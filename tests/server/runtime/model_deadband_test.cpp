// The force-model deadband: a model goes out when the device would feel the
// difference (Weber fraction of the force, at the tool and 1 mm deeper),
// on a change of contact state, and as a keep-alive — else it is held.
#include "hapsim/runtime/model_deadband.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>

namespace hapsim::service {
namespace {

constexpr std::int64_t kMsNs = 1'000'000;

core::LocalForceModel Contact(double stiffness_N_per_m) {
  core::LocalForceModel m;
  m.state = core::ContactState::kContact;
  m.normal_W = Eigen::Vector3d::UnitZ();
  m.stiffness_N_per_m = stiffness_N_per_m;
  return m;
}

core::ToolInput ToolAt(double z_m) {
  core::ToolInput t;
  t.valid = true;
  t.tip_W_m = Eigen::Vector3d(0, 0, z_m);
  return t;
}

ModelDeadbandConfig Jnd7() {
  ModelDeadbandConfig c;
  c.jnd = 0.07;
  c.keepalive_s = 0.025;
  return c;
}

TEST(ModelDeadband, WithoutAJndEveryModelGoesOut) {
  ModelDeadband deadband(ModelDeadbandConfig{});
  for (int i = 0; i < 5; ++i) EXPECT_TRUE(deadband.Offer(Contact(500), ToolAt(-0.002), i * kMsNs));
}

TEST(ModelDeadband, AnUnchangedModelGoesOutOnlyAsAKeepAlive) {
  ModelDeadband deadband(Jnd7());
  EXPECT_TRUE(deadband.Offer(Contact(500), ToolAt(-0.002), 0));  // the first always
  EXPECT_FALSE(deadband.Offer(Contact(500), ToolAt(-0.002), kMsNs));
  EXPECT_FALSE(deadband.Offer(Contact(500), ToolAt(-0.002), 25 * kMsNs - 1));
  EXPECT_TRUE(deadband.Offer(Contact(500), ToolAt(-0.002), 25 * kMsNs));
  EXPECT_FALSE(deadband.Offer(Contact(500), ToolAt(-0.002), 26 * kMsNs));
}

TEST(ModelDeadband, AChangeUnderTheJndIsHeldAndOneOverItGoesOut) {
  ModelDeadband deadband(Jnd7());
  ASSERT_TRUE(deadband.Offer(Contact(500), ToolAt(-0.002), 0));          // 1.00 N held by the device
  EXPECT_FALSE(deadband.Offer(Contact(530), ToolAt(-0.002), kMsNs));     // 1.06 N: 5.7 % of 1.06, not felt
  EXPECT_TRUE(deadband.Offer(Contact(540), ToolAt(-0.002), 2 * kMsNs));  // 1.08 N: 7.4 %, felt
  // Compared with what the device now holds (540), not the first model.
  EXPECT_FALSE(deadband.Offer(Contact(560), ToolAt(-0.002), 3 * kMsNs));
}

TEST(ModelDeadband, AStiffnessChangeAtTheSurfaceIsSeenOneMillimetreIn) {
  // At zero penetration both models give 0 N; 1 mm in, 0.5 vs 1.0 N.
  ModelDeadband deadband(Jnd7());
  ASSERT_TRUE(deadband.Offer(Contact(500), ToolAt(0.0), 0));
  EXPECT_TRUE(deadband.Offer(Contact(1000), ToolAt(0.0), kMsNs));
}

TEST(ModelDeadband, ANewContactStateAlwaysGoesOut) {
  // Above the surface a contact model and a free one both give 0 N.
  ModelDeadband deadband(Jnd7());
  ASSERT_TRUE(deadband.Offer(core::LocalForceModel{}, ToolAt(0.005), 0));
  EXPECT_TRUE(deadband.Offer(Contact(500), ToolAt(0.005), kMsNs));
  EXPECT_TRUE(deadband.Offer(core::LocalForceModel{}, ToolAt(0.005), 2 * kMsNs));
}

TEST(ModelDeadband, BelowTheFloorSmallForcesAreJudgedAgainstIt) {
  // 0.002 N -> 0.003 N is 50 % of the force but 5 % of the 0.02 N floor.
  ModelDeadband deadband(Jnd7());
  core::LocalForceModel a, b;
  a.feedforward_W_N = Eigen::Vector3d(0, 0, 0.002);
  b.feedforward_W_N = Eigen::Vector3d(0, 0, 0.003);
  ASSERT_TRUE(deadband.Offer(a, ToolAt(0.0), 0));
  EXPECT_FALSE(deadband.Offer(b, ToolAt(0.0), kMsNs));
}

TEST(ModelDeadband, ANonFiniteModelGoesOutForTheBridgeToRefuse) {
  ModelDeadband deadband(Jnd7());
  ASSERT_TRUE(deadband.Offer(Contact(500), ToolAt(-0.002), 0));
  EXPECT_TRUE(deadband.Offer(Contact(std::numeric_limits<double>::quiet_NaN()), ToolAt(-0.002), kMsNs));
}

TEST(ModelDeadband, AfterForgetTheNextModelGoesOut) {
  ModelDeadband deadband(Jnd7());
  ASSERT_TRUE(deadband.Offer(Contact(500), ToolAt(-0.002), 0));
  deadband.Forget();
  EXPECT_TRUE(deadband.Offer(Contact(500), ToolAt(-0.002), kMsNs));
}

}  // namespace
}  // namespace hapsim::service
