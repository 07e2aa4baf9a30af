// The pose deadband: a pose goes out when it leaves the deadband around
// where the server extrapolates the last one sent, when the velocity or the
// buttons change, and as a keep-alive — a tool at constant velocity sends
// keep-alives only.
#include "hapsim/servo/pose_deadband.h"

#include <gtest/gtest.h>

#include <limits>

namespace hapsim::bridge {
namespace {

constexpr std::int64_t kPoseMsNs = 1'000'000;

SensedPose PoseAt(std::int64_t t_ns, double z_m, double vz_m_per_s) {
  SensedPose p;
  p.t_device_ns = t_ns;
  p.tool.valid = true;
  p.tool.tip_W_m = Eigen::Vector3d(0, 0, z_m);
  p.tool.velocity_W_m_per_s = Eigen::Vector3d(0, 0, vz_m_per_s);
  return p;
}

PoseDeadbandConfig Band() {
  PoseDeadbandConfig c;
  c.position_m = 0.00005;      // 0.05 mm
  c.velocity_m_per_s = 0.005;  // 5 mm/s
  c.keepalive_s = 0.025;
  return c;
}

TEST(PoseDeadband, WithoutABandEveryPoseGoesOut) {
  PoseDeadband band(PoseDeadbandConfig{});
  for (int k = 0; k < 5; ++k) EXPECT_TRUE(band.Offer(PoseAt(k * kPoseMsNs, 0.0, 0.0)));
}

TEST(PoseDeadband, ConstantVelocitySendsKeepAlivesOnly) {
  PoseDeadband band(Band());
  int sent = 0;
  for (int k = 0; k < 1000; ++k) sent += band.Offer(PoseAt(k * kPoseMsNs, 0.01 - 0.01 * k * 1e-3, -0.01));
  EXPECT_EQ(sent, 40);  // the first, then one per 25 ms
}

TEST(PoseDeadband, LeavingTheExtrapolationByMoreThanTheBandSends) {
  PoseDeadband band(Band());
  ASSERT_TRUE(band.Offer(PoseAt(0, 0.0, 0.0)));
  EXPECT_FALSE(band.Offer(PoseAt(kPoseMsNs, -0.00004, 0.0)));      // 0.04 mm off: inside
  EXPECT_TRUE(band.Offer(PoseAt(2 * kPoseMsNs, -0.00006, 0.0)));   // 0.06 mm off: out
  EXPECT_FALSE(band.Offer(PoseAt(3 * kPoseMsNs, -0.00006, 0.0)));  // measured from the new one
}

TEST(PoseDeadband, AVelocityChangeSendsBeforeThePositionDrifts) {
  // A stop: the server would keep moving the tool on at 10 mm/s.
  PoseDeadband band(Band());
  ASSERT_TRUE(band.Offer(PoseAt(0, 0.0, -0.01)));
  EXPECT_FALSE(band.Offer(PoseAt(kPoseMsNs, -0.00001, -0.006)));  // 4 mm/s slower: inside
  EXPECT_TRUE(band.Offer(PoseAt(2 * kPoseMsNs, -0.00002, 0.0)));
}

TEST(PoseDeadband, AButtonChangeSends) {
  PoseDeadband band(Band());
  ASSERT_TRUE(band.Offer(PoseAt(0, 0.0, 0.0)));
  SensedPose pressed = PoseAt(kPoseMsNs, 0.0, 0.0);
  pressed.tool.buttons = 1;
  EXPECT_TRUE(band.Offer(pressed));
}

TEST(PoseDeadband, ANanPoseSends) {
  PoseDeadband band(Band());
  ASSERT_TRUE(band.Offer(PoseAt(0, 0.0, 0.0)));
  EXPECT_TRUE(band.Offer(PoseAt(kPoseMsNs, std::numeric_limits<double>::quiet_NaN(), 0.0)));
}

}  // namespace
}  // namespace hapsim::bridge
