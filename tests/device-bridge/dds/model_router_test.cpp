// hapsim-load's per-device dispatch: a model reaches exactly the inbox of
// the device (and session) it names; anything else is counted and dropped.
#include "hapsim/bridge/model_router.h"

#include <gtest/gtest.h>

#include <cstring>

#include "backends/synthetic_device.h"
#include "hapsim/common/clock.h"

namespace hapsim::bridge {
namespace {

hapsim_dds_LocalForceModel ModelFor(std::uint32_t device_id, const char* session, std::uint64_t seq,
                                    std::uint64_t server_instance = 0xA) {
  hapsim_dds_LocalForceModel m{};
  m.device_id = device_id;
  std::strncpy(m.session, session, sizeof m.session - 1);
  m.seq = seq;
  m.server_instance = server_instance;
  return m;
}

constexpr std::int64_t kMs = 1'000'000;

class ModelRouterTest : public ::testing::Test {
 protected:
  ModelRouter router_{100, {"room-a", "room-b", "room-c"}};

  bool HasNew(std::size_t device, ReceivedModel* out) { return router_.inbox(device).TakeIfNew(out); }
};

TEST_F(ModelRouterTest, AModelForDeviceJLandsOnlyInJsInboxWithItsArrivalStamp) {
  router_.Route(ModelFor(101, "room-b", 42), 123456789);
  ReceivedModel got;
  ASSERT_TRUE(HasNew(1, &got));
  EXPECT_EQ(got.seq, 42u);
  EXPECT_EQ(got.received_ns, 123456789);
  EXPECT_FALSE(HasNew(0, &got));
  EXPECT_FALSE(HasNew(2, &got));
  EXPECT_EQ(router_.models_routed(1), 1u);
  EXPECT_EQ(router_.models_routed(0), 0u);
}

TEST_F(ModelRouterTest, AModelForAnUnknownDeviceIsCountedAndReachesNoInbox) {
  router_.Route(ModelFor(99, "room-a", 1), 1);   // below the first id
  router_.Route(ModelFor(103, "room-a", 1), 1);  // past the last
  EXPECT_EQ(router_.models_for_unknown_devices(), 2u);
  ReceivedModel got;
  for (std::size_t i = 0; i < router_.devices(); ++i) EXPECT_FALSE(HasNew(i, &got)) << "device " << i;
}

TEST_F(ModelRouterTest, AModelForOurDeviceButAnotherSessionIsCountedAndDropped) {
  router_.Route(ModelFor(100, "room-b", 1), 1);
  EXPECT_EQ(router_.models_for_other_sessions(), 1u);
  EXPECT_EQ(router_.models_for_unknown_devices(), 0u);
  ReceivedModel got;
  EXPECT_FALSE(HasNew(0, &got));
}

TEST_F(ModelRouterTest, TheNewestModelOfADeviceWins) {
  router_.Route(ModelFor(102, "room-c", 1), 1);
  router_.Route(ModelFor(102, "room-c", 2), 2);
  ReceivedModel got;
  ASSERT_TRUE(HasNew(2, &got));
  EXPECT_EQ(got.seq, 2u);
  EXPECT_EQ(router_.models_routed(2), 2u);
}

// Two servers on one domain both serving "room-a": the device keeps the
// first server's models, at 1 kHz interleaved with the second's, and never
// hands the second's to the servo loop.
TEST_F(ModelRouterTest, ADeviceFollowsTheFirstServerAndDropsAndCountsAnothersInterleavedModels) {
  constexpr std::uint64_t kFirst = 0x1111, kSecond = 0x2222;
  for (std::uint64_t i = 0; i < 100; ++i) {
    const auto t = static_cast<std::int64_t>(i) * kMs;
    router_.Route(ModelFor(100, "room-a", i, kFirst), t);
    router_.Route(ModelFor(100, "room-a", 10'000 + i, kSecond), t + kMs / 2);
    ReceivedModel got;
    ASSERT_TRUE(HasNew(0, &got)) << "tick " << i;
    EXPECT_EQ(got.server_instance, kFirst) << "tick " << i;
    EXPECT_EQ(got.seq, i);
  }
  EXPECT_EQ(router_.followed_server(0), kFirst);
  EXPECT_EQ(router_.models_routed(0), 100u);
  EXPECT_EQ(router_.models_from_other_servers(0), 100u);
  EXPECT_EQ(router_.server_switches(0), 0u);
  EXPECT_EQ(router_.followed_server(1), 0u) << "another device follows nobody before its first model";
}

// A restarted server (a new instance) is followed only once the old one has
// been silent for the switch delay — never while the old one still talks.
TEST_F(ModelRouterTest, ADeviceSwitchesServerOnlyAfterItsServerHasBeenSilentForTheSwitchDelay) {
  constexpr std::uint64_t kOld = 0x1111, kNew = 0x2222;
  router_.Route(ModelFor(100, "room-a", 1, kOld), 0);
  const std::int64_t just_before = ModelRouter::kServerSilenceBeforeSwitch_ns - 1;
  router_.Route(ModelFor(100, "room-a", 1, kNew), just_before);
  EXPECT_EQ(router_.followed_server(0), kOld);
  EXPECT_EQ(router_.models_from_other_servers(0), 1u);
  router_.Route(ModelFor(100, "room-a", 2, kNew), ModelRouter::kServerSilenceBeforeSwitch_ns);
  EXPECT_EQ(router_.followed_server(0), kNew);
  EXPECT_EQ(router_.server_switches(0), 1u);
  ReceivedModel got;
  ASSERT_TRUE(HasNew(0, &got));
  EXPECT_EQ(got.server_instance, kNew);
  EXPECT_EQ(got.seq, 2u);
  // The old server speaking again is now the other one.
  router_.Route(ModelFor(100, "room-a", 3, kOld), ModelRouter::kServerSilenceBeforeSwitch_ns + kMs);
  EXPECT_FALSE(HasNew(0, &got));
  EXPECT_EQ(router_.models_from_other_servers(0), 2u);
}

}  // namespace
}  // namespace hapsim::bridge

namespace hapsim::bridge {
namespace {

// Row 49 of docs/reliability.md: a state number this bridge does not know
// is read as free — the feed-forward force only, no spring into the tissue.
TEST(ReceivedModelTest, AnUnknownContactStateIsReadAsFree) {
  hapsim_dds_LocalForceModel message{};
  message.state = 7;
  message.normal[2] = 1.0;
  message.stiffness_n_per_m = 500.0;
  message.feedforward_n[0] = 0.02;
  const ReceivedModel model = ToReceivedModel(message, common::SteadyNowNs());
  EXPECT_EQ(model.model.state, core::ContactState::kFree);
  SyntheticScript pressed;  // held 2 mm into the tissue, where the spring would give 1 N
  pressed.kind = "hold";
  pressed.start_height_m = 0.0;
  pressed.entry_W_m = Eigen::Vector3d(0, 0, -0.002);
  SyntheticDevice device(pressed);
  ServoChannel channel(&device, ChannelConfig{7, 0.001, {}, 1024});
  common::LatestValue<ReceivedModel> inbox;
  channel.Sense(0.0);
  inbox.Publish(model);
  const ChannelTick& tick = channel.Actuate(inbox);
  EXPECT_EQ(tick.requested_W_N, Eigen::Vector3d(0.02, 0, 0));
}

}  // namespace
}  // namespace hapsim::bridge

namespace hapsim::bridge {
namespace {

// The header's deadband fields, in the units of the wire (µs, ms), arrive
// in the channel's (ns, s).
TEST(ReceivedModelTest, TheHeldTimeAndThePromisedGapArriveInNanosecondsAndSeconds) {
  hapsim_dds_LocalForceModel message{};
  message.echo_pose_held_us = 12'345;
  message.next_model_within_ms = 25;
  const ReceivedModel model = ToReceivedModel(message, 7);
  EXPECT_EQ(model.echo_pose_held_ns, 12'345'000);
  EXPECT_DOUBLE_EQ(model.next_model_within_s, 0.025);
  EXPECT_EQ(model.received_ns, 7);
}

}  // namespace
}  // namespace hapsim::bridge
