// hapsim-load's servo thread against an instant in-process "server" that
// answers every pose with a model echoing it: each device sees only its own
// echoes, in order, with a round trip.
#include "hapsim/load/load_runner.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cstring>

#include "hapsim/common/clock.h"

namespace hapsim::bridge {
namespace {

// Devices in lockstep (one clock, one wake per period), unless own_clocks.
std::vector<LoadDevicePlan> ThreeDevices(bool own_clocks = false) {
  LoadPlanOptions o;
  o.devices = 3;
  o.first_device_id = 40;
  o.script.kind = "random_walk";
  if (!own_clocks) {
    o.clock_phase_spread = 0.0;
    o.clock_rate_ppm = 0.0;
  }
  return PlanDevices(o);
}

std::vector<std::string> SessionsOf(const std::vector<LoadDevicePlan>& plan) {
  std::vector<std::string> sessions;
  for (const auto& d : plan) sessions.push_back(d.session);
  return sessions;
}

// The "server": answers every pose at once with a model echoing it. It runs
// on the servo thread, which is then the inboxes' only producer.
PoseWriter EchoingServer(ModelRouter& router) {
  return [&router](const SensedPose& pose) {
    hapsim_dds_LocalForceModel model{};
    model.device_id = pose.device_id;
    const std::string session = router.session(pose.device_id - router.first_device_id());
    session.copy(model.session, sizeof model.session - 1);
    model.echo_pose_seq = pose.seq;
    router.Route(model, common::SteadyNowNs());
    return true;
  };
}

LoadRunConfig ShortRun() {
  LoadRunConfig c;
  c.run_seconds = 0.05;
  return c;
}

TEST(LoadRunner, EachDeviceReceivesItsOwnEchoesInOrderWithARoundTrip) {
  const auto plan = ThreeDevices();
  ModelRouter router(plan.front().device_id, SessionsOf(plan));
  LoadRunner runner(plan, ShortRun(), &router, EchoingServer(router));
  std::atomic<bool> stop{false};
  const LoadReport r = runner.Run(stop);
  ASSERT_EQ(r.devices.size(), 3u);
  EXPECT_GT(r.servo.ticks, 10u);
  for (const auto& d : r.devices) {
    EXPECT_EQ(d.flow.poses_sent, r.servo.ticks) << d.session;
    EXPECT_EQ(d.flow.models_used, d.flow.poses_sent) << d.session;
    EXPECT_EQ(d.first_echo_seq, 0u) << d.session;
    EXPECT_EQ(d.last_echo_seq, d.flow.poses_sent - 1) << d.session;
    EXPECT_EQ(d.flow.echo_regressions, 0u) << d.session;
    EXPECT_EQ(d.flow.round_trip_s.count, d.flow.poses_sent) << d.session;
    EXPECT_EQ(d.flow.safety.disarms, 0u) << d.session;
  }
  EXPECT_EQ(r.total.flow.round_trip_s.count, 3 * r.servo.ticks);
  EXPECT_EQ(r.models_for_other_sessions + r.models_for_unknown_devices, 0u);
}

// --interval-s: the run cut into intervals whose pooled samples add up to
// the run's (the pooled window holds every sample of so short a run), the
// largest of them the run's largest.
TEST(LoadRunner, IntervalsPartitionTheRunsRoundTrips) {
  const auto plan = ThreeDevices();
  ModelRouter router(plan.front().device_id, SessionsOf(plan));
  LoadRunConfig config;
  config.run_seconds = 0.25;
  config.interval_s = 0.1;
  LoadRunner runner(plan, config, &router, EchoingServer(router));
  std::atomic<bool> stop{false};
  const LoadReport r = runner.Run(stop);
  ASSERT_EQ(r.intervals.size(), 3u);  // ends 0.1, 0.2 and the last, shorter one
  EXPECT_DOUBLE_EQ(r.intervals[0].end_s, 0.1);
  EXPECT_DOUBLE_EQ(r.intervals[1].end_s, 0.2);
  EXPECT_GT(r.intervals[2].end_s, 0.2);
  EXPECT_LE(r.intervals[2].end_s, 0.3);
  std::size_t round_trips = 0;
  double largest = 0.0;
  for (const auto& i : r.intervals) {
    EXPECT_GT(i.round_trip_s.count, 0u);
    EXPECT_LE(i.round_trip_s.p50, i.round_trip_s.p99);
    EXPECT_LE(i.round_trip_s.p99, i.round_trip_s.max);
    round_trips += i.round_trip_s.count;
    largest = std::max(largest, i.round_trip_s.max);
  }
  EXPECT_EQ(round_trips, r.total.flow.round_trip_s.count);
  EXPECT_EQ(largest, r.total.flow.round_trip_s.max);
  EXPECT_EQ(r.intervals_dropped, 0u);
}

// Each device on its own clock (phases a third of a period apart, rates
// +-500 ppm): every device still sends one pose per tick of its own clock
// and gets each echo back in order; the thread wakes for the devices' ticks
// separately (at least once per device tick of the busiest clock).
TEST(LoadRunner, DevicesOnTheirOwnClocksEachSendOnePosePerTickAndGetTheirEchoes) {
  const auto plan = ThreeDevices(/*own_clocks=*/true);
  ASSERT_TRUE(HasOwnClocks(plan));
  ModelRouter router(plan.front().device_id, SessionsOf(plan));
  LoadRunConfig config;
  config.run_seconds = 0.2;
  LoadRunner runner(plan, config, &router, EchoingServer(router));
  std::atomic<bool> stop{false};
  const LoadReport r = runner.Run(stop);
  std::uint64_t most = 0;
  for (const auto& d : r.devices) {
    // 200 ticks in 0.2 s at 1 kHz +-500 ppm (the first at the device's phase); a stall re-anchors and loses some.
    EXPECT_GE(d.flow.poses_sent, 190u) << d.session;
    EXPECT_LE(d.flow.poses_sent, 200u) << d.session;
    EXPECT_EQ(d.flow.models_used, d.flow.poses_sent) << d.session;
    EXPECT_EQ(d.last_echo_seq, d.flow.poses_sent - 1) << d.session;
    EXPECT_EQ(d.flow.echo_regressions, 0u) << d.session;
    most = std::max(most, d.flow.poses_sent);
  }
  EXPECT_GE(r.servo.ticks, most);
  EXPECT_LE(r.servo.ticks, 3 * most);
}

TEST(LoadRunner, RefusedPoseWritesAreCountedAndNoModelMeansNoModelState) {
  const auto plan = ThreeDevices();
  ModelRouter router(plan.front().device_id, SessionsOf(plan));
  LoadRunner runner(plan, ShortRun(), &router, [](const SensedPose&) { return false; });
  std::atomic<bool> stop{false};
  const LoadReport r = runner.Run(stop);
  for (const auto& d : r.devices) {
    EXPECT_EQ(d.flow.poses_sent, 0u);
    EXPECT_EQ(d.flow.pose_write_failures, r.servo.ticks);
    EXPECT_EQ(d.final_watchdog, WatchdogState::kNoModel);
  }
  EXPECT_EQ(r.total.devices_with_models, 0u);
}

TEST(StatsWindowPerDevice, HoldsABoundedRunWithinTheBudget) {
  EXPECT_GE(StatsWindowPerDevice(20.0, 1000.0, 64), 20'000u);
  EXPECT_LE(StatsWindowPerDevice(3600.0, 1000.0, 64) * 64, std::size_t{1} << 22);
}

}  // namespace
}  // namespace hapsim::bridge
