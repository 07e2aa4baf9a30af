// The watchdog's second age: how old the physics a model describes is (the
// round trip plus the gap since it arrived), so a constant network delay is
// seen, not only a stream that stopped. Thresholds: warn 50 ms, fade from
// 1 s to zero at 2 s (safety_config.h); numbers exact.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "backends/synthetic_device.h"
#include "hapsim/common/clock.h"
#include "hapsim/servo/force_safety.h"
#include "hapsim/servo/servo_channel.h"
#include "safety_test_setup.h"

namespace hapsim::bridge {
namespace {

constexpr double kTickS = 0.001;
const Eigen::Vector3d kOneNewton(0, 0, 1.0);

// One tick of a chain with only the clamp and the watchdog acting.
Eigen::Vector3d Tick(ForceSafety& s, double gap_s, double physics_age_s) {
  SafetyInput in;
  in.requested_W_N = kOneNewton;
  in.model_age_s = gap_s;
  in.physics_age_s = physics_age_s;
  in.dt_s = kTickS;
  return s.Apply(in);
}

TEST(PhysicsAgeWatchdog, AConstantRoundTripAboveFiftyMillisecondsWarnsOnceAtFullForce) {
  ForceSafety s(test::QuietChain());
  EXPECT_NEAR(Tick(s, 0.001, 0.049).z(), 1.0, 1e-12);
  EXPECT_EQ(s.state(), WatchdogState::kFresh);
  for (int i = 0; i < 100; ++i) EXPECT_NEAR(Tick(s, 0.001, 0.100).z(), 1.0, 1e-12);
  EXPECT_EQ(s.state(), WatchdogState::kWarn);
  EXPECT_EQ(s.counters().delay_warnings, 1u);
  EXPECT_EQ(s.counters().warnings, 1u);
  EXPECT_EQ(s.counters().fades, 0u);
}

TEST(PhysicsAgeWatchdog, FadesLinearlyFromOneSecondToZeroAtTwo) {
  ForceSafety s(test::QuietChain());
  EXPECT_NEAR(Tick(s, 0.001, 0.999).z(), 1.0, 1e-12);
  EXPECT_NEAR(Tick(s, 0.001, 1.250).z(), 0.75, 1e-12);
  EXPECT_EQ(s.state(), WatchdogState::kFading);
  EXPECT_NEAR(Tick(s, 0.001, 1.900).z(), 0.1, 1e-12);
  EXPECT_EQ(Tick(s, 0.001, 2.000).norm(), 0.0);
  EXPECT_EQ(s.state(), WatchdogState::kDisarmed);
  EXPECT_EQ(s.counters().disarms, 1u);
}

TEST(PhysicsAgeWatchdog, TheSmallerFactorOfTheTwoAgesScalesTheForce) {
  ForceSafety s(test::QuietChain());
  // Gap 75 ms: half (fade 50 -> 100 ms); physics 1.8 s: a fifth (1 -> 2 s).
  EXPECT_NEAR(Tick(s, 0.075, 1.800).z(), 0.2, 1e-12);
  EXPECT_NEAR(Tick(s, 0.090, 1.100).z(), 0.2, 1e-12);  // now the gap is the smaller: 0.2 vs 0.9
}

TEST(PhysicsAgeWatchdog, ReArmsOnlyWhenTheGapIsFreshAndThePhysicsBelowItsFadeStart) {
  ForceSafety s(test::QuietChain());
  Tick(s, 0.001, 2.5);
  ASSERT_EQ(s.state(), WatchdogState::kDisarmed);
  EXPECT_EQ(Tick(s, 0.001, 1.2).norm(), 0.0);  // a fresh arrival of 1.2 s old physics would fade: stays off
  EXPECT_EQ(s.state(), WatchdogState::kDisarmed);
  EXPECT_NEAR(Tick(s, 0.001, 0.3).z(), 1.0, 1e-12);  // a slow but usable link: back, in warn
  EXPECT_EQ(s.state(), WatchdogState::kWarn);
  // A stall on that link disarms through the gap, and a fresh model re-arms with the physics still 0.3 s old.
  Tick(s, 0.150, 0.45);
  ASSERT_EQ(s.state(), WatchdogState::kDisarmed);
  EXPECT_NEAR(Tick(s, 0.001, 0.3).z(), 1.0, 1e-12);
}

TEST(PhysicsAgeWatchdog, AnUnknownPhysicsAgeLeavesTheGapAlone) {
  ForceSafety s(test::QuietChain());
  EXPECT_NEAR(Tick(s, 0.030, -1.0).z(), 1.0, 1e-12);
  EXPECT_EQ(s.state(), WatchdogState::kWarn);
  EXPECT_EQ(s.counters().delay_warnings, 0u);
}

TEST(PhysicsAgeWatchdog, RejectsUnorderedPhysicsAges) {
  SafetyConfig c;
  c.delay_fade_start_age_s = c.delay_disarm_age_s;
  EXPECT_THROW(ValidateSafetyConfig(c), std::invalid_argument);
  c = SafetyConfig{};
  c.delay_warn_age_s = 0.0;
  EXPECT_THROW(ValidateSafetyConfig(c), std::invalid_argument);
  c = SafetyConfig{};
  c.delay_disarm_age_s = std::nan("");
  EXPECT_THROW(ValidateSafetyConfig(c), std::invalid_argument);
}

// The channel times the physics from when the stylus was at the echoed pose,
// whatever the model's arrival time says.
class PhysicsAgeChannelTest : public ::testing::Test {
 protected:
  static SyntheticScript Hold() {
    SyntheticScript script;
    script.kind = "hold";
    script.start_height_m = 0.0;
    script.entry_W_m = Eigen::Vector3d(0, 0, -0.002);
    return script;
  }
  SyntheticDevice device_{Hold()};
  common::LatestValue<ReceivedModel> inbox_;
  ServoChannel channel_{&device_, ChannelConfig{1, kTickS, test::QuietChain(), 1024}};
};

TEST_F(PhysicsAgeChannelTest, AModelJustArrivedForAPoseSensedEarlierIsAsOldAsThatPose) {
  channel_.Sense(0.0);
  const std::int64_t pose0_ns = channel_.pose().t_device_ns;
  channel_.Actuate(inbox_);
  while (common::SteadyNowNs() - pose0_ns < 5'000'000) {
  }  // 5 ms pass: the model below answers a pose that old
  channel_.Sense(0.001);
  inbox_.Publish(test::ContactModel(0, channel_.pose().t_device_ns));  // arrives now
  const ChannelTick& tick = channel_.Actuate(inbox_);
  EXPECT_EQ(tick.model_age_s, 0.0);
  EXPECT_GE(tick.physics_age_s, 0.005);
  EXPECT_NEAR(tick.physics_age_s, static_cast<double>(channel_.pose().t_device_ns - pose0_ns) * 1e-9, 1e-12);
  // The next tick holds the same model: its physics ages with the clock.
  channel_.Sense(0.002);
  const std::int64_t pose2_ns = channel_.pose().t_device_ns;
  EXPECT_NEAR(channel_.Actuate(inbox_).physics_age_s, static_cast<double>(pose2_ns - pose0_ns) * 1e-9, 1e-12);
  EXPECT_EQ(channel_.PhysicsAge().count, 2u);
}

TEST_F(PhysicsAgeChannelTest, AModelAnsweringAPoseThisChannelNeverSensedGivesNoForce) {
  // Echo 99 was never sensed here: another run's pose (a restarted bridge) or
  // one older than the remembered 4 s — no one knows how old its physics is.
  channel_.Sense(0.0);
  inbox_.Publish(test::ContactModel(99, common::SteadyNowNs()));
  const ChannelTick& tick = channel_.Actuate(inbox_);
  EXPECT_EQ(tick.physics_age_s, std::numeric_limits<double>::infinity());
  EXPECT_EQ(tick.force_W_N.norm(), 0.0);
  EXPECT_EQ(channel_.watchdog(), WatchdogState::kDisarmed);
  // The server then answers one of our poses: force returns.
  channel_.Sense(0.001);
  inbox_.Publish(test::ContactModel(1, common::SteadyNowNs()));
  EXPECT_NEAR(channel_.Actuate(inbox_).force_W_N.z(), 1.0, 1e-9);  // 2 mm x 500 N/m
  EXPECT_EQ(channel_.watchdog(), WatchdogState::kFresh);
}

}  // namespace
}  // namespace hapsim::bridge
