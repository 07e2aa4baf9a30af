// The channel hands the chain what its stages need: the device's limits,
// the stylus's velocity and buttons. A 2 mm press into a 500 N/m contact
// (1 N) on a still device, every stage quiet but the one checked.
#include <gtest/gtest.h>

#include <memory>

#include "hapsim/common/clock.h"
#include "hapsim/servo/servo_channel.h"
#include "safety_test_setup.h"

// Its own namespace: the test files are compiled in batches (unity build).
namespace hapsim::bridge::servo_channel_safety_test {
namespace {

class ChannelSafety : public ::testing::Test {
 protected:
  ChannelSafety() { device_.reading.tip_W_m = Eigen::Vector3d(0, 0, -0.002); }
  void Build(const SafetyConfig& safety) {
    ChannelConfig config;
    config.safety = safety;
    channel_ = std::make_unique<ServoChannel>(&device_, config);
  }
  // One tick with a fresh copy of a contact model of stiffness k; returns
  // the commanded force along z.
  double Tick(double k_N_per_m = 500.0) {
    channel_->Sense(0.0);
    ReceivedModel m;
    m.model.state = core::ContactState::kContact;
    m.model.stiffness_N_per_m = k_N_per_m;
    m.echo_pose_seq = channel_->pose().seq;
    m.received_ns = common::SteadyNowNs();
    inbox_.Publish(m);
    return channel_->Actuate(inbox_).force_W_N.z();
  }

  test::StillDevice device_;
  common::LatestValue<ReceivedModel> inbox_;
  std::unique_ptr<ServoChannel> channel_;
};

TEST_F(ChannelSafety, TheArmButtonOfTheReadingArmsAndDisarms) {
  SafetyConfig c = test::QuietChain();
  c.arm_button_mask = 0b1;
  Build(c);
  EXPECT_EQ(Tick(), 0.0);
  device_.reading.buttons = 0b1;
  EXPECT_NEAR(Tick(), 1.0, 1e-12);
  device_.reading.buttons = 0;
  EXPECT_NEAR(Tick(), 1.0, 1e-12);
  device_.reading.buttons = 0b1;
  EXPECT_EQ(Tick(), 0.0);
  EXPECT_EQ(device_.last_force_W_N.norm(), 0.0);
  EXPECT_EQ(channel_->safety_counters().arm_toggles, 2u);
}

TEST_F(ChannelSafety, TheVelocityOfTheReadingIsLimited) {
  SafetyConfig c = test::QuietChain();
  c.max_velocity_m_per_s = 0.6;
  Build(c);
  device_.reading.velocity_W_m_per_s = Eigen::Vector3d(0.7, 0, 0);
  EXPECT_EQ(Tick(), 0.0);
  device_.reading.velocity_W_m_per_s = Eigen::Vector3d(0.5, 0, 0);
  EXPECT_NEAR(Tick(), 1.0, 1e-12);
  EXPECT_EQ(channel_->safety_counters().velocity_limited, 1u);
}

// The device's 2 N peak clamps a 2.5 N request (5 mm at 500 N/m).
TEST_F(ChannelSafety, TheDevicesPeakForceClamps) {
  device_.limits.max_force_N = 2.0;
  device_.reading.tip_W_m = Eigen::Vector3d(0, 0, -0.005);
  Build(test::QuietChain());
  EXPECT_NEAR(Tick(), 2.0, 1e-12);
  EXPECT_EQ(channel_->safety_counters().clamped, 1u);
}

}  // namespace
}  // namespace hapsim::bridge::servo_channel_safety_test
