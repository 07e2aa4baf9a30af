// One device's servo tick: round trips come from the send time remembered
// for the echoed seq, and a stale model drives the watchdog's event counters.
#include "hapsim/servo/servo_channel.h"

#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <string>
#include <utility>
#include <vector>

#include "backends/synthetic_device.h"
#include "hapsim/common/clock.h"
#include "safety_test_setup.h"

namespace hapsim::bridge {
namespace {

constexpr std::int64_t kMsNs = 1'000'000;

SyntheticScript PressedTwoMillimetres() {
  SyntheticScript script;
  script.kind = "hold";
  script.start_height_m = 0.0;
  script.entry_W_m = Eigen::Vector3d(0, 0, -0.002);
  return script;
}

using test::ContactModel;

class ServoChannelTest : public ::testing::Test {
 protected:
  SyntheticDevice device_{PressedTwoMillimetres()};
  common::LatestValue<ReceivedModel> inbox_;
  // Without the ramp-in: the first tick expects the rise limit's 0.05 N.
  ServoChannel channel_{&device_, ChannelConfig{7, 0.001, test::WithoutRampIn(), 1024}};
};

TEST_F(ServoChannelTest, SenseFillsThePoseWithThisDeviceSessionAndNextSeq) {
  channel_.Sense(0.0);
  channel_.Actuate(inbox_);
  channel_.Sense(0.001);
  EXPECT_EQ(channel_.pose().device_id, 7u);
  EXPECT_EQ(channel_.pose().seq, 1u);
  EXPECT_DOUBLE_EQ(channel_.pose().tool.tip_W_m.z(), -0.002);
}

TEST_F(ServoChannelTest, AModelEchoingAPoseGivesTheTimeFromSensingToArrival) {
  channel_.Sense(0.0);
  const std::int64_t sent_ns = channel_.pose().t_device_ns;
  channel_.Actuate(inbox_);
  channel_.Sense(0.001);
  inbox_.Publish(ContactModel(0, sent_ns + 3 * kMsNs));
  const ChannelTick& tick = channel_.Actuate(inbox_);
  EXPECT_NEAR(tick.round_trip_s, 0.003, 1e-12);
  EXPECT_EQ(channel_.RoundTrip().count, 1u);
  EXPECT_EQ(channel_.counters().models_taken, 1u);
  EXPECT_EQ(channel_.counters().first_echo_seq, 0u);
}

TEST_F(ServoChannelTest, NoNewModelMeansNoRoundTripThisTick) {
  channel_.Sense(0.0);
  inbox_.Publish(ContactModel(0, common::SteadyNowNs()));
  channel_.Actuate(inbox_);
  channel_.Sense(0.001);
  EXPECT_LT(channel_.Actuate(inbox_).round_trip_s, 0.0);
  EXPECT_EQ(channel_.RoundTrip().count, 1u);
  EXPECT_EQ(channel_.ModelAge().count, 2u);  // the held model still has an age each tick
}

TEST_F(ServoChannelTest, AnEchoOfAPoseNeverSentGivesNoRoundTrip) {
  channel_.Sense(0.0);
  inbox_.Publish(ContactModel(99, common::SteadyNowNs()));
  EXPECT_LT(channel_.Actuate(inbox_).round_trip_s, 0.0);
  EXPECT_EQ(channel_.RoundTrip().count, 0u);
}

TEST_F(ServoChannelTest, AModelOvertakenInTransitIsDiscardedAndCounted) {
  // Echo 1 arrives after echo 2 (reordered): the tool keeps the force of the
  // newer model, 2 mm x 500 N/m, not echo 1's 5 mm. Poses 0-3 were sensed first.
  for (int k = 0; k < 4; ++k) {
    channel_.Sense(0.0);
    channel_.Actuate(inbox_);
  }
  for (std::uint64_t echo : {0u, 2u, 1u, 3u}) {
    channel_.Sense(0.0);
    ReceivedModel m = ContactModel(echo, common::SteadyNowNs());
    if (echo == 1) m.model.anchor_W_m.z() = 0.003;  // the overtaken model would ask for 5 mm
    inbox_.Publish(m);
    const ChannelTick& tick = channel_.Actuate(inbox_);
    if (echo == 1) {
      EXPECT_NEAR(tick.requested_W_N.z(), 1.0, 1e-9);
    }
  }
  EXPECT_EQ(channel_.counters().echo_regressions, 1u);
  EXPECT_EQ(channel_.counters().models_taken, 3u);
  EXPECT_EQ(channel_.counters().first_echo_seq, 0u);
  EXPECT_EQ(channel_.counters().last_echo_seq, 3u);
}

// Models arriving in a clump within one tick: the newest is rendered, and the
// server's models this device never rendered are counted (lost ones too).
TEST_F(ServoChannelTest, ModelsOfTheServersSequenceNeverRenderedAreCounted) {
  for (int k = 0; k < 4; ++k) {
    channel_.Sense(0.0);
    channel_.Actuate(inbox_);
  }
  const auto publish = [&](std::uint64_t seq, std::uint64_t echo) {
    ReceivedModel m = ContactModel(echo, common::SteadyNowNs());
    m.seq = seq;
    m.server_instance = 42;
    inbox_.Publish(m);
  };
  channel_.Sense(0.0);
  publish(1, 0);
  channel_.Actuate(inbox_);
  channel_.Sense(0.0);
  publish(2, 1);
  publish(3, 2);
  publish(4, 3);  // three in one tick: 2 and 3 are overwritten in the inbox
  channel_.Actuate(inbox_);
  EXPECT_EQ(channel_.counters().models_unused, 2u);
  EXPECT_EQ(channel_.counters().last_echo_seq, 3u);
  channel_.Sense(0.0);
  ReceivedModel other = ContactModel(3, common::SteadyNowNs());
  other.seq = 90;
  other.server_instance = 7;  // another server's sequence is not this one's gap
  inbox_.Publish(other);
  channel_.Actuate(inbox_);
  EXPECT_EQ(channel_.counters().models_unused, 2u);
}

TEST_F(ServoChannelTest, AfterAStallAnOlderEchoIsTakenNotDiscarded) {
  // Held model echoes 100 and was received 30 ms ago (past the 20 ms warning):
  // the stream stalled (e.g. the server restarted), so a model echoing 50 is
  // taken - discarding it would keep the device on a stale model.
  channel_.Sense(0.0);
  inbox_.Publish(ContactModel(100, common::SteadyNowNs() - 30 * kMsNs));
  channel_.Actuate(inbox_);
  channel_.Sense(0.0);
  inbox_.Publish(ContactModel(50, common::SteadyNowNs()));
  channel_.Actuate(inbox_);
  EXPECT_EQ(channel_.counters().echo_regressions, 0u);
  EXPECT_EQ(channel_.counters().models_taken, 2u);
  EXPECT_EQ(channel_.counters().last_echo_seq, 50u);
}

TEST_F(ServoChannelTest, AStaleModelRaisesWarningFadeAndDisarmOnceEachAndEndsAtZeroForce) {
  // The same model ever older: received 30, then 70, then 200 ms before the tick.
  for (const std::int64_t age_ms : {30, 70, 200, 210}) {
    channel_.Sense(0.0);
    inbox_.Publish(ContactModel(0, common::SteadyNowNs() - age_ms * kMsNs));
    channel_.Actuate(inbox_);
  }
  EXPECT_EQ(channel_.safety_counters().warnings, 1u);
  EXPECT_EQ(channel_.safety_counters().fades, 1u);
  EXPECT_EQ(channel_.safety_counters().disarms, 1u);
  EXPECT_EQ(channel_.watchdog(), WatchdogState::kDisarmed);
  EXPECT_EQ(device_.last_force_W_N().norm(), 0.0);
}

// A server that held the pose 4 ms (extrapolating the tool) before the tick
// that answered it: the round trip is the 3 ms left, and the model's physics
// is of the stylus 4 ms after that pose (simulated clock).
TEST_F(ServoChannelTest, TheTimeTheServerHeldThePoseIsNotPartOfTheRoundTrip) {
  const std::int64_t t0 = 1'000'000'000;
  channel_.Sense(0.0, t0);
  channel_.Actuate(inbox_);
  ReceivedModel model = ContactModel(0, t0 + 7 * kMsNs);
  model.echo_pose_held_ns = 4 * kMsNs;
  channel_.Sense(0.007, t0 + 7 * kMsNs);
  inbox_.Publish(model);
  const ChannelTick& tick = channel_.Actuate(inbox_);
  EXPECT_NEAR(tick.round_trip_s, 0.003, 1e-12);
  EXPECT_NEAR(tick.physics_age_s, 0.003, 1e-12);
}

// Within the gap the server promised (a 25 ms keep-alive) a held model is
// not late: the watchdog stays fresh at 24 ms and the physics age stays the
// model's round trip; past the promise the stream ages from there (warning
// 20 ms later, at a 45 ms gap, so the dead server is still caught).
TEST_F(ServoChannelTest, AHeldModelIsNotLateWithinTheGapTheServerPromised) {
  const std::int64_t t0 = 1'000'000'000;
  channel_.Sense(0.0, t0);
  channel_.Actuate(inbox_);
  ReceivedModel model = ContactModel(0, t0 + 1 * kMsNs);
  model.next_model_within_s = 0.025;
  inbox_.Publish(model);
  for (const int gap_ms : {0, 24, 44}) {
    channel_.Sense(0.001 * (1 + gap_ms), t0 + (1 + gap_ms) * kMsNs);
    const ChannelTick& t = channel_.Actuate(inbox_);
    EXPECT_NEAR(t.model_age_s, gap_ms * 1e-3, 1e-12);
    EXPECT_NEAR(t.model_overdue_s, std::max(0, gap_ms - 25) * 1e-3, 1e-12);
    EXPECT_NEAR(t.physics_age_s, 0.001 + std::max(0, gap_ms - 25) * 1e-3, 1e-12);
    EXPECT_EQ(channel_.watchdog(), WatchdogState::kFresh) << gap_ms << " ms";
  }
  channel_.Sense(0.046, t0 + 46 * kMsNs);
  channel_.Actuate(inbox_);
  EXPECT_EQ(channel_.watchdog(), WatchdogState::kWarn);
  EXPECT_EQ(channel_.safety_counters().warnings, 1u);
}

// A server promising a long gap is believed for 100 ms at most: past that
// the stream is late (a 250 ms gap under a 10 s promise is 150 ms overdue:
// disarmed).
TEST_F(ServoChannelTest, APromiseOfALongGapCountsForATenthOfASecondAtMost) {
  const std::int64_t t0 = 1'000'000'000;
  channel_.Sense(0.0, t0);
  inbox_.Publish([&] {
    ReceivedModel m = ContactModel(0, t0);
    m.next_model_within_s = 10.0;
    return m;
  }());
  channel_.Actuate(inbox_);
  channel_.Sense(0.25, t0 + 250 * kMsNs);
  const ChannelTick& t = channel_.Actuate(inbox_);
  EXPECT_NEAR(t.model_overdue_s, 0.15, 1e-12);
  EXPECT_EQ(channel_.watchdog(), WatchdogState::kDisarmed);
}

TEST_F(ServoChannelTest, AFreshContactModelPushesTheToolOutOfTheTissue) {
  channel_.Sense(0.0);
  inbox_.Publish(ContactModel(0, common::SteadyNowNs()));
  const ChannelTick& tick = channel_.Actuate(inbox_);
  EXPECT_NEAR(tick.requested_W_N.z(), 1.0, 1e-9);  // 500 N/m * 2 mm
  EXPECT_NEAR(tick.force_W_N.z(), 0.05, 1e-9);     // first tick: rise limit 50 N/s * 1 ms
  EXPECT_EQ(device_.last_force_W_N(), tick.force_W_N);
}

// Row 50: a NaN in any numeric field of a model never reaches the motors as
// NaN, and never exceeds the clamp; a NaN force is zeroed and counted.
TEST_F(ServoChannelTest, ANanInAnyModelFieldNeverReachesTheDevice) {
  const std::vector<std::pair<const char*, std::function<void(core::LocalForceModel&)>>> poisons = {
      {"anchor", [](auto& m) { m.anchor_W_m.z() = std::nan(""); }},
      {"normal", [](auto& m) { m.normal_W.z() = std::nan(""); }},
      {"stiffness", [](auto& m) { m.stiffness_N_per_m = std::nan(""); }},
      {"damping", [](auto& m) { m.damping_Ns_per_m = std::nan(""); }},
      {"feedforward", [](auto& m) { m.feedforward_W_N.y() = std::nan(""); }},
      {"release penetration", [](auto& m) { m.release_penetration_m = std::nan(""); }},
      {"release stiffness",
       [](auto& m) {
         m.release_penetration_m = 1e-3;  // pressed 2 mm: released
         m.release_stiffness_N_per_m = std::nan("");
       }},
  };
  for (const auto& [name, poison] : poisons) {
    SyntheticDevice device{PressedTwoMillimetres()};
    ServoChannel channel{&device, ChannelConfig{7, 0.001, {}, 1024}};
    common::LatestValue<ReceivedModel> inbox;
    std::uint64_t non_finite_requests = 0;
    for (int tick = 0; tick < 100; ++tick) {  // 100 ms: past the rise limit's ramp
      channel.Sense(tick * 0.001);
      ReceivedModel model = ContactModel(0, common::SteadyNowNs());
      poison(model.model);
      inbox.Publish(model);
      if (!channel.Actuate(inbox).requested_W_N.allFinite()) ++non_finite_requests;
      const Eigen::Vector3d force = device.last_force_W_N();
      ASSERT_TRUE(force.allFinite()) << name << " tick " << tick;
      ASSERT_LE(force.norm(), SafetyConfig{}.max_force_N + 1e-12) << name << " tick " << tick;
    }
    EXPECT_EQ(channel.safety_counters().non_finite, non_finite_requests) << name;
    // The feed-forward is added as it is: this poison must reach the safety stage.
    if (std::string(name) == "feedforward") {
      EXPECT_EQ(non_finite_requests, 100u);
    }
  }
}

}  // namespace
}  // namespace hapsim::bridge

namespace hapsim::bridge {
namespace {

// The transparency reference: a model that echoes pose S is evaluated at
// pose S (where the physics computed it), with the server's stiffness, not
// at the stylus now and not capped to what the device can render.
TEST(ServoChannelPhysicsReference, AModelIsEvaluatedAtThePoseItEchoesAsTheServerSentIt) {
  SyntheticScript script;
  script.kind = "constant_speed";  // down at 10 mm/s from the surface
  script.start_height_m = 0.0;
  script.depth_m = 0.01;
  SyntheticDevice device(script);
  common::LatestValue<ReceivedModel> inbox;
  ChannelConfig config{7, 0.001, test::WithoutRampIn(), 1024};
  config.physics_reference = true;
  ServoChannel channel(&device, config);
  double z_of_pose_10 = 0.0;
  for (int k = 0; k <= 30; ++k) {
    channel.Sense(k * 0.001);
    if (k == 10) z_of_pose_10 = channel.pose().tool.tip_W_m.z();
    if (k == 30) {
      ReceivedModel m = ContactModel(10, common::SteadyNowNs());
      m.model.stiffness_N_per_m = 2000.0;  // above the device's 700 N/m cap
      inbox.Publish(m);
    }
    const ChannelTick& tick = channel.Actuate(inbox);
    if (k < 30) continue;
    ASSERT_GE(tick.round_trip_s, 0.0);
    ASSERT_LT(z_of_pose_10, -0.00005);  // the tip was below the surface at pose 10, deeper now
    EXPECT_NEAR(tick.physics_at_echo_W_N.z(), 2000.0 * -z_of_pose_10, 1e-9);
    EXPECT_LT(tick.requested_W_N.z(), 700.0 * -channel.pose().tool.tip_W_m.z() + 1e-9);  // rendered: capped, here
  }
}

}  // namespace
}  // namespace hapsim::bridge
