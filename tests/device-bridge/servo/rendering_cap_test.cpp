// The rendering cap: a model is never rendered stiffer or more damped than
// the device renders stably (CHAI3D's table by default, the device's own
// value when lower), counted once per model; its geometry stays.
#include "hapsim/servo/rendering_cap.h"

#include <gtest/gtest.h>

#include "hapsim/common/clock.h"
#include "hapsim/servo/servo_channel.h"
#include "safety_test_setup.h"

// Its own namespace: the test files are compiled in batches (unity build).
namespace hapsim::bridge::rendering_cap_test {
namespace {

core::LocalForceModel StiffNeedleModel() {
  core::LocalForceModel m;
  m.state = core::ContactState::kPunctured;
  m.anchor_W_m = Eigen::Vector3d(0.001, 0.002, 0.0);
  m.stiffness_N_per_m = 1000.0;
  m.stick_stiffness_N_per_m = 900.0;
  m.tip_stiffness_N_per_m = 800.0;
  m.damping_Ns_per_m = 8.0;
  m.drag_damping_Ns_per_m = 6.0;
  m.drag_N = 0.3;
  return m;
}

TEST(RenderingCap, EveryStiffnessAndDampingIsCappedTheGeometryStays) {
  core::LocalForceModel m = StiffNeedleModel();
  EXPECT_TRUE(CapRendering(&m, 700.0, 5.0));
  EXPECT_EQ(m.stiffness_N_per_m, 700.0);
  EXPECT_EQ(m.stick_stiffness_N_per_m, 700.0);
  EXPECT_EQ(m.tip_stiffness_N_per_m, 700.0);
  EXPECT_EQ(m.damping_Ns_per_m, 5.0);
  EXPECT_EQ(m.drag_damping_Ns_per_m, 5.0);
  EXPECT_EQ(m.anchor_W_m, StiffNeedleModel().anchor_W_m);
  EXPECT_EQ(m.drag_N, 0.3);
}

TEST(RenderingCap, AModelWithinTheCapsIsUntouched) {
  core::LocalForceModel m = StiffNeedleModel();
  EXPECT_FALSE(CapRendering(&m, 1000.0, 8.0));  // caps equal to its values: nothing above them
  EXPECT_EQ(m.stiffness_N_per_m, 1000.0);
  EXPECT_EQ(m.damping_Ns_per_m, 8.0);
}

TEST(RenderingCap, ForceSafetyCapsAtTheLowerOfConfigAndDeviceAndCountsModels) {
  DeviceLimits touch;
  touch.max_stiffness_N_per_m = 400.0;
  touch.max_damping_Ns_per_m = 4.0;
  ForceSafety s(SafetyConfig{}, touch);
  core::LocalForceModel m = StiffNeedleModel();
  s.CapModel(&m);
  EXPECT_EQ(m.stiffness_N_per_m, 400.0);
  EXPECT_EQ(m.drag_damping_Ns_per_m, 4.0);
  core::LocalForceModel soft;
  soft.stiffness_N_per_m = 300.0;
  s.CapModel(&soft);
  EXPECT_EQ(soft.stiffness_N_per_m, 300.0);
  EXPECT_EQ(s.counters().models_capped, 1u);
}

// Through the channel: a 1000 N/m contact on a Touch-like device (400 N/m)
// pressed 2 mm asks for 400 x 0.002 = 0.8 N, not 2 N.
TEST(RenderingCap, TheChannelRendersATakenModelAtTheDevicesStiffness) {
  test::StillDevice device;
  device.reading.tip_W_m = Eigen::Vector3d(0, 0, -0.002);
  device.limits.max_stiffness_N_per_m = 400.0;
  ChannelConfig config;
  config.safety = test::QuietChain();
  ServoChannel channel(&device, config);
  common::LatestValue<ReceivedModel> inbox;
  ReceivedModel m;
  m.model.state = core::ContactState::kContact;
  m.model.stiffness_N_per_m = 1000.0;
  channel.Sense(0.0);
  m.received_ns = common::SteadyNowNs();
  inbox.Publish(m);
  const ChannelTick& tick = channel.Actuate(inbox);
  EXPECT_NEAR(tick.requested_W_N.z(), 0.8, 1e-12);
  EXPECT_NEAR(device.last_force_W_N.z(), 0.8, 1e-12);
  EXPECT_EQ(channel.safety_counters().models_capped, 1u);
}

}  // namespace
}  // namespace hapsim::bridge::rendering_cap_test
