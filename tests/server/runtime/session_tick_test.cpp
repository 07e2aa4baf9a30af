// Session ticks driven by hand (no pool, synthetic clock): the tick allocates
// nothing, replaying its TickInputs reaches the same state hash, one device
// owns a session, deadlines follow the device, lateness is counted, and
// snapshots copy the mesh only for someone who reads it.
#include <gtest/gtest.h>

#include <algorithm>
#include <memory>
#include <vector>

#include "core/allocation_counter.h"
#include "hapsim/common/clock.h"
#include "hapsim/runtime/session.h"

namespace hapsim::service {
namespace {

constexpr std::int64_t kT0Ns = 1'000'000'000'000;  // synthetic steady clock origin
constexpr std::int64_t kPeriodNs = 1'000'000;      // 1 kHz

struct CapturedModels {
  std::uint64_t count = 0;
  ForceModelMessage last{};
};

// An in-memory port: keeps the newest force model.
class CapturingPort : public SessionPort {
 public:
  explicit CapturingPort(CapturedModels* models) : models_(models) {}
  bool WriteForceModel(const ForceModelMessage& m) override {
    ++models_->count;
    models_->last = m;
    return true;
  }

 private:
  CapturedModels* models_;
};

std::unique_ptr<Session> MakeSession(const std::string& scene, CapturedModels* models) {
  SessionConfig config;
  config.id = "tick-test";
  config.scene = scene;
  return std::make_unique<Session>(config, core::MakeScene({scene, {}}), std::make_shared<CapturingPort>(models));
}

// A needle above the centre moving down 1 µm per tick from 2 mm above z = 0.
PoseSample PressingPose(std::uint64_t seq, std::uint32_t device, std::int64_t now_ns) {
  PoseSample p;
  p.tool.valid = true;
  p.tool.tip_W_m = Eigen::Vector3d(0.001, -0.002, 0.002 - 1e-6 * static_cast<double>(seq));
  p.tool.velocity_W_m_per_s = Eigen::Vector3d(0, 0, -1e-3);
  p.device_id = device;
  p.seq = seq;
  p.received_ns = now_ns;
  return p;
}

class EveryScene : public ::testing::TestWithParam<std::string> {};

std::vector<std::string> SceneNames() {
  std::vector<std::string> names;
  for (const auto& scene : core::SceneCatalog()) names.push_back(scene.name);
  return names;
}

INSTANTIATE_TEST_SUITE_P(Catalogue, EveryScene, ::testing::ValuesIn(SceneNames()),
                         [](const auto& test_info) { return test_info.param; });

TEST_P(EveryScene, TheTickAllocatesNothingWhilePressingAndPublishingSnapshots) {
  CapturedModels models;
  auto session = MakeSession(GetParam(), &models);
  session->counters().viewers.connected.store(1);  // watched: every snapshot copies the mesh
  std::shared_ptr<const SceneSnapshot> snapshot;
  std::int64_t now = kT0Ns;
  std::uint64_t seq = 0;
  auto tick = [&] {
    session->OfferPose(PressingPose(seq++, 1, now));
    session->RunTick(now, now);
    session->TakeSnapshot(&snapshot);  // as the frame pump does: it holds the newest
    now += kPeriodNs;
  };
  for (int i = 0; i < 200; ++i) tick();  // warm-up: contact begins, topology arrays shared once
  std::uint64_t allocations = 0;
  {
    hapsim::test::ScopedAllocationCount counting;
    for (int i = 0; i < 2000; ++i) tick();
    allocations = counting.Count();
  }
  EXPECT_EQ(allocations, 0u);
  EXPECT_EQ(models.count, 2200u);
  EXPECT_EQ(session->counters().tick.snapshots_skipped.load(), 0u);
  EXPECT_GT(session->counters().tick.peak_tool_force_N.load(), 0.0);  // the needle really pressed
}

TEST_P(EveryScene, ReplayingTheRecordedTickInputsReachesTheSameStateHash) {
  CapturedModels models;
  auto session = MakeSession(GetParam(), &models);
  std::vector<TickInput> recorded;
  recorded.reserve(4000);
  session->SetTickObserver([&recorded](const TickInput& in) { recorded.push_back(in); });
  std::int64_t now = kT0Ns;
  std::uint64_t seq = 0;
  for (int i = 0; i < 3000; ++i) {
    // Poses at an irregular cadence (every 1-3 ticks), a pause, a reset, a
    // device that goes quiet past the pose timeout.
    if (i % 3 != 2 && (i < 2200 || i > 2600)) session->OfferPose(PressingPose(seq++, 4, now));
    if (i == 900) session->RequestPause(true);
    if (i == 1000) session->RequestPause(false);
    if (i == 1500) session->RequestReset();
    session->RunTick(now, now);
    now += kPeriodNs;
  }
  ASSERT_EQ(recorded.size(), 3000u);
  auto replica = core::MakeScene({GetParam(), {}});
  const std::uint64_t fresh_hash = replica->StateHash();
  for (const auto& in : recorded) StepScene(*replica, in, session->config().tick_period_s);
  EXPECT_EQ(replica->StateHash(), session->scene().StateHash());
  EXPECT_NE(replica->StateHash(), fresh_hash);
  EXPECT_DOUBLE_EQ(replica->SimTime_s(), session->scene().SimTime_s());
}

TEST(SessionTick, ASecondDeviceCannotDriveAnOwnedSession) {
  CapturedModels models;
  auto session = MakeSession("tissue_block", &models);
  std::int64_t now = kT0Ns;
  for (std::uint64_t seq = 0; seq < 50; ++seq) {
    ASSERT_EQ(session->OfferPose(PressingPose(seq, 1, now)), PoseVerdict::kAccepted);
    auto intruder = PressingPose(1000 + seq, 2, now);
    intruder.tool.tip_W_m.z() = -0.01;  // would press 1 cm deep
    EXPECT_EQ(session->OfferPose(intruder), PoseVerdict::kOtherDevice);
    session->RunTick(now, now);
    now += kPeriodNs;
  }
  EXPECT_EQ(session->counters().poses.from_other_devices.load(), 50u);
  EXPECT_EQ(session->counters().poses.received.load(), 50u);
  EXPECT_EQ(models.last.device_id, 1u);
  EXPECT_EQ(models.last.echo_pose_seq, 49u);
  EXPECT_EQ(session->counters().tick.owning_device_id.load(), 1u);
}

TEST(SessionTick, AStaleOrDuplicatePoseFromTheOwnerMovesNothingAndIsCounted) {
  CapturedModels models;
  auto session = MakeSession("tissue_block", &models);
  std::int64_t now = kT0Ns;
  ASSERT_EQ(session->OfferPose(PressingPose(10, 1, now)), PoseVerdict::kAccepted);
  session->RunTick(now, now);
  now += kPeriodNs;
  auto late = PressingPose(9, 1, now);  // overtaken by seq 10: must not pull the tool back
  late.tool.tip_W_m.z() = -0.01;
  EXPECT_EQ(session->OfferPose(late), PoseVerdict::kStale);
  EXPECT_EQ(session->OfferPose(PressingPose(10, 1, now)), PoseVerdict::kStale);  // duplicate
  session->RunTick(now, now);
  EXPECT_EQ(models.last.echo_pose_seq, 10u);
  EXPECT_EQ(session->counters().poses.stale.load(), 2u);
  EXPECT_EQ(session->counters().poses.received.load(), 1u);
}

// Jitter delivers poses in clumps: a tick takes the newest and counts the
// ones of the device's sequence no tick used (superseded, or never arrived).
TEST(SessionTick, ATickTakesTheNewestOfSeveralPosesAndCountsTheOnesNoTickUsed) {
  CapturedModels models;
  auto session = MakeSession("tissue_block", &models);
  std::int64_t now = kT0Ns;
  ASSERT_EQ(session->OfferPose(PressingPose(10, 1, now)), PoseVerdict::kAccepted);
  session->RunTick(now, now);
  now += kPeriodNs;
  for (const std::uint64_t seq : {11u, 12u, 13u}) session->OfferPose(PressingPose(seq, 1, now));  // one clump
  session->RunTick(now, now);
  EXPECT_EQ(models.last.echo_pose_seq, 13u);
  EXPECT_EQ(session->counters().tick.poses_unused.load(), 2u);  // 11 and 12
  now += kPeriodNs;
  session->OfferPose(PressingPose(17, 1, now));  // 14-16 lost on the way
  session->RunTick(now, now);
  EXPECT_EQ(session->counters().tick.poses_unused.load(), 5u);
  now += kPeriodNs;
  session->RunTick(now, now);  // no new pose: nothing more is unused
  EXPECT_EQ(session->counters().tick.poses_unused.load(), 5u);
}

TEST(SessionTick, NoForceModelOnceThePoseIsOlderThanTheTimeout) {
  CapturedModels models;
  auto session = MakeSession("tissue_block", &models);
  const std::int64_t timeout_ns = static_cast<std::int64_t>(session->config().pose_timeout_s * 1e9);
  session->OfferPose(PressingPose(0, 1, kT0Ns));
  session->RunTick(kT0Ns, kT0Ns);
  EXPECT_EQ(models.count, 1u);
  EXPECT_TRUE(session->counters().tick.device_streaming.load());
  session->RunTick(kT0Ns + timeout_ns, kT0Ns + timeout_ns);  // exactly at the timeout: still present
  EXPECT_EQ(models.count, 2u);
  session->RunTick(kT0Ns + timeout_ns + 1, kT0Ns + timeout_ns + 1);
  EXPECT_EQ(models.count, 2u);
  EXPECT_FALSE(session->counters().tick.device_streaming.load());
}

TEST(SessionTick, TheDeviceClocksTheSessionAndTheTimerOnlyCoversALatePose) {
  CapturedModels models;
  auto session = MakeSession("tissue_block", &models);
  const std::int64_t slack_ns = static_cast<std::int64_t>(session->config().pose_slack_s * 1e9);
  // No device: the next tick is the next point of the shared 1 kHz grid.
  const std::int64_t due0 = kT0Ns + 123'456;
  EXPECT_EQ(session->RunTick(due0, due0), kT0Ns + kPeriodNs);
  // A pose ticks the session; the timer waits one period plus the slack.
  const std::int64_t arrival = kT0Ns + 1'500'000;
  session->OfferPose(PressingPose(0, 1, arrival));
  const std::int64_t due1 = session->PoseDueNs(arrival);
  EXPECT_EQ(due1, arrival);  // the previous tick started more than half a period ago
  const std::int64_t timer = session->RunTick(due1, due1);
  EXPECT_EQ(timer, arrival + kPeriodNs + slack_ns);
  // The pose was late: the timer tick reuses it and keeps the period.
  EXPECT_EQ(session->RunTick(timer, timer), timer + kPeriodNs);
  EXPECT_EQ(session->counters().tick.device_clocked_ticks.load(), 1u);
}

TEST(SessionTick, APoseAfterATimerTickIsAnsweredAtOnceAndTheTicksKeepTheirPace) {
  CapturedModels models;
  auto session = MakeSession("tissue_block", &models);
  const std::int64_t slack_ns = static_cast<std::int64_t>(session->config().pose_slack_s * 1e9);
  const std::int64_t first = kT0Ns + 1'500'000;
  session->OfferPose(PressingPose(0, 1, first));
  const std::int64_t timer = session->RunTick(first, first);
  EXPECT_EQ(session->RunTick(timer, timer), timer + kPeriodNs);  // the next pose is late (or held back)
  // It comes 0.1 ms after that timer tick: answered at once...
  const std::int64_t arrival = timer + 100'000;
  session->OfferPose(PressingPose(1, 1, arrival));
  EXPECT_EQ(session->PoseDueNs(arrival), arrival);
  // ...and the deadline after it is where it would be had the tick waited
  // half a period after the timer tick: the same ticks per second.
  EXPECT_EQ(session->RunTick(arrival, arrival), timer + kPeriodNs / 2 + kPeriodNs + slack_ns);
  // A device faster than the tick rate cannot speed sim time up: a pose
  // right after a tick that took one waits half a period after it.
  session->OfferPose(PressingPose(2, 1, arrival + 100'000));
  EXPECT_EQ(session->PoseDueNs(arrival + 100'000), arrival + kPeriodNs / 2);
  EXPECT_EQ(session->counters().tick.device_clocked_ticks.load(), 2u);
}

TEST(SessionTick, ATickStartedMoreThanOnePeriodAfterItWasDueIsLate) {
  CapturedModels models;
  auto session = MakeSession("tissue_block", &models);
  session->RunTick(kT0Ns, kT0Ns + kPeriodNs);  // exactly one period: not late
  EXPECT_EQ(session->counters().tick.late_ticks.load(), 0u);
  session->RunTick(kT0Ns + kPeriodNs, kT0Ns + 3 * kPeriodNs);
  EXPECT_EQ(session->counters().tick.late_ticks.load(), 1u);
  EXPECT_EQ(session->counters().tick.max_lateness_ns.load(), 2 * kPeriodNs);
  EXPECT_EQ(session->counters().tick.ticks.load(), 2u);
}

TEST(SessionTick, SimTimeAdvancesOnePeriodPerTickWhateverTheWallClock) {
  CapturedModels models;
  auto session = MakeSession("tissue_block", &models);
  std::int64_t now = kT0Ns;
  for (int i = 0; i < 100; ++i) {
    session->RunTick(now, now);
    now += (i % 2 ? 3 : 1) * kPeriodNs / 2;  // irregular wall-clock spacing
  }
  EXPECT_NEAR(session->scene().SimTime_s(), 0.1, 1e-12);
}

TEST(SessionTick, BetweenPosesTheToolMovesOnAlongItsVelocityForAtMostTheHorizon) {
  CapturedModels models;
  SessionConfig config;
  config.id = "extrapolation";
  config.pose_extrapolation_s = 0.010;
  Session session(config, core::MakeScene({"tissue_block", {}}), std::make_shared<CapturingPort>(&models));
  std::vector<TickInput> inputs;
  session.SetTickObserver([&](const TickInput& in) { inputs.push_back(in); });
  const PoseSample pose = PressingPose(0, 1, kT0Ns);  // 1 mm/s down
  session.OfferPose(pose);
  for (int k = 0; k <= 15; ++k) session.RunTick(kT0Ns + k * kPeriodNs, kT0Ns + k * kPeriodNs);
  ASSERT_EQ(inputs.size(), 16u);
  for (int k = 0; k <= 15; ++k) {
    const double ahead_s = std::min(k, 10) * 1e-3;  // held after the 10 ms horizon
    EXPECT_NEAR(inputs[k].tool.tip_W_m.z(), pose.tool.tip_W_m.z() - 1e-3 * ahead_s, 1e-15) << "tick " << k;
    EXPECT_EQ(inputs[k].tool.tip_W_m.x(), pose.tool.tip_W_m.x());
    EXPECT_EQ(inputs[k].pose_seq, 0u);  // the model still answers the pose it came from
  }
}

TEST(SessionTick, WithAModelDeadbandAToolHeldStillGetsKeepAlivesOnly) {
  // Pressed 1 mm into the block and held: once the tissue settles, the
  // force stops changing and models go out every keep-alive (25 ms).
  CapturedModels models;
  SessionConfig config;
  config.id = "deadband";
  config.model_deadband.jnd = 0.07;
  config.model_deadband.keepalive_s = 0.025;
  Session session(config, core::MakeScene({"tissue_block", {}}), std::make_shared<CapturingPort>(&models));
  std::int64_t now = kT0Ns;
  for (std::uint64_t seq = 0; seq < 2000; ++seq) {
    PoseSample p = PressingPose(seq, 1, now);
    p.tool.tip_W_m.z() = -0.001;
    p.tool.velocity_W_m_per_s.setZero();
    session.OfferPose(p);
    session.RunTick(now, now);
    if (seq == 999) models.count = 0;  // settled: count the second second only
    now += kPeriodNs;
  }
  EXPECT_EQ(models.count, 40u);  // 1000 ms / 25 ms
  EXPECT_EQ(session.counters().tick.force_models_held.load() + session.counters().tick.force_models_sent.load(), 2000u);
  EXPECT_GT(models.last.model.stiffness_N_per_m, 0.0);
  EXPECT_EQ(models.last.model.state, core::ContactState::kContact);
  EXPECT_DOUBLE_EQ(models.last.next_model_within_s, 0.025);  // the promise the device's watchdog allows for
}

// A model says how long the session had held the pose it answers (the
// device then knows its physics is that much newer than the pose): 0 on the
// tick the pose arrived for, then one period more each tick without a new
// pose. Without a deadband it promises nothing (a model every tick).
TEST(SessionTick, AModelSaysHowLongThePoseItAnswersWasHeld) {
  CapturedModels models;
  SessionConfig config;
  config.id = "held";
  Session session(config, core::MakeScene({"tissue_block", {}}), std::make_shared<CapturingPort>(&models));
  session.OfferPose(PressingPose(5, 1, kT0Ns));
  for (int k = 0; k <= 3; ++k) {
    session.RunTick(kT0Ns + k * kPeriodNs, kT0Ns + k * kPeriodNs);
    EXPECT_EQ(models.last.echo_pose_seq, 5u);
    EXPECT_EQ(models.last.echo_pose_held_ns, k * kPeriodNs) << "tick " << k;
    EXPECT_EQ(models.last.next_model_within_s, 0.0);
  }
  session.OfferPose(PressingPose(6, 1, kT0Ns + 4 * kPeriodNs));
  session.RunTick(kT0Ns + 4 * kPeriodNs, kT0Ns + 4 * kPeriodNs);
  EXPECT_EQ(models.last.echo_pose_seq, 6u);
  EXPECT_EQ(models.last.echo_pose_held_ns, 0);
}

// Ticks until the session publishes its next snapshot (a frame: 17 ticks at
// 60 Hz) and takes it, as the frame pump does.
std::shared_ptr<const SceneSnapshot> TickOneFrame(Session& session, std::int64_t* now_ns) {
  std::shared_ptr<const SceneSnapshot> snapshot;
  for (int i = 0; i < 100 && !session.TakeSnapshot(&snapshot); ++i) {
    session.RunTick(*now_ns, *now_ns);
    *now_ns += kPeriodNs;
  }
  return snapshot;
}

// The mesh copy at the frame rate is for viewers and GetSnapshot only: a
// session nobody watches publishes snapshots without it (the first, at
// creation, has it), a connected viewer or a request brings it back, and a
// snapshot that has it holds the scene's vertices as they are.
TEST(SessionTick, ASnapshotCarriesTheMeshOnlyWhileAViewerWatchesOrSomeoneAskedForIt) {
  CapturedModels models;
  auto session = MakeSession("tissue_block", &models);
  std::int64_t now = kT0Ns;
  std::shared_ptr<const SceneSnapshot> first;
  ASSERT_TRUE(session->TakeSnapshot(&first));
  EXPECT_EQ(first->id, 1u);
  EXPECT_TRUE(first->has_mesh);

  session->WantMeshUntil(common::SteadyNowNs() - 1);  // asked for until a moment past: no copy
  auto unwatched = TickOneFrame(*session, &now);
  ASSERT_TRUE(unwatched);
  EXPECT_FALSE(unwatched->has_mesh);
  EXPECT_NEAR(unwatched->sim_time_s, session->scene().SimTime_s(), 1e-12);  // the rest is this instant's

  session->counters().viewers.connected.store(1);
  auto watched = TickOneFrame(*session, &now);
  ASSERT_TRUE(watched);
  ASSERT_TRUE(watched->has_mesh);
  const Eigen::Matrix3Xd& vertices = session->scene().Vertices_m();
  ASSERT_EQ(watched->vertices_m.cols(), vertices.cols());
  EXPECT_EQ(watched->vertices_m, vertices);
  EXPECT_EQ(watched->vertex_slots, session->scene().Topology().Vertices().HighWater());

  session->counters().viewers.connected.store(0);
  EXPECT_FALSE(TickOneFrame(*session, &now)->has_mesh);
  session->WantMeshUntil(common::SteadyNowNs() + 60'000'000'000);  // asked for a minute
  session->WantMeshUntil(common::SteadyNowNs() - 1);               // a later, shorter ask does not shorten it
  EXPECT_TRUE(TickOneFrame(*session, &now)->has_mesh);
}

}  // namespace
}  // namespace hapsim::service
