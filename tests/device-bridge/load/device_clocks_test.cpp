// The devices' own servo clocks, driven in virtual time (no sleeping): each
// device ticks exactly at its phase plus whole periods of its own rate, and
// a stalled thread re-anchors the clocks instead of bursting.
#include "hapsim/load/device_clocks.h"

#include <gtest/gtest.h>

#include <cmath>
#include <vector>

namespace hapsim::bridge {
namespace {

TEST(DeviceClocks, EachDeviceTicksAtItsPhasePlusWholePeriodsOfItsOwnRate) {
  const double period_s = 1e-3;
  const std::vector<double> phases_s = {1e-4, 3.5e-4, 6e-4};  // no tick falls on the 10 s boundary
  const std::vector<double> ppm = {-500.0, 0.0, 500.0};
  DeviceClocks clocks(phases_s, ppm, period_s);
  std::vector<std::size_t> due;
  std::vector<double> due_times_s;
  due.reserve(3);
  due_times_s.reserve(3);
  std::vector<std::uint64_t> ticks(3, 0);
  const double run_s = 10.0;
  // Wake exactly at every due time, as a thread with no sleep overshoot would.
  for (double now_s = clocks.NextDueS(); now_s < run_s; now_s = clocks.NextDueS()) {
    clocks.TakeDue(now_s, &due, &due_times_s);
    ASSERT_FALSE(due.empty());
    for (std::size_t k = 0; k < due.size(); ++k) {
      const std::size_t i = due[k];
      // Tick n of device i at phase_i + n * period / (1 + ppm_i 1e-6), to rounding.
      const double expected_s = phases_s[i] + static_cast<double>(ticks[i]) * period_s / (1.0 + ppm[i] * 1e-6);
      ASSERT_NEAR(due_times_s[k], expected_s, 1e-12) << "device " << i << " tick " << ticks[i];
      ++ticks[i];
    }
  }
  // Over 10 s: 10 000 ticks at the nominal rate, 5 fewer at -500 ppm, 5 more at +500 ppm.
  EXPECT_EQ(ticks[0], 9995u);
  EXPECT_EQ(ticks[1], 10000u);
  EXPECT_EQ(ticks[2], 10005u);
  EXPECT_EQ(clocks.reanchors(), 0u);
}

TEST(DeviceClocks, AWakeLateByLessThanTenPeriodsCatchesUpTickByTick) {
  DeviceClocks clocks({0.0}, {0.0}, 1e-3);
  std::vector<std::size_t> due;
  std::vector<double> due_times_s;
  due.reserve(1);
  due_times_s.reserve(1);
  clocks.TakeDue(0.0, &due, &due_times_s);     // tick 0
  clocks.TakeDue(0.0055, &due, &due_times_s);  // woke 4.5 periods late: one tick per wake
  ASSERT_EQ(due.size(), 1u);
  EXPECT_DOUBLE_EQ(due_times_s[0], 1e-3);
  EXPECT_DOUBLE_EQ(clocks.NextDueS(), 2e-3);  // the missed ticks are still owed, one per wake
  EXPECT_EQ(clocks.reanchors(), 0u);
}

TEST(DeviceClocks, AStallOfMoreThanTenPeriodsReanchorsOnNowInsteadOfBursting) {
  DeviceClocks clocks({0.0, 5e-4}, {0.0, 0.0}, 1e-3);
  std::vector<std::size_t> due;
  std::vector<double> due_times_s;
  due.reserve(2);
  due_times_s.reserve(2);
  clocks.TakeDue(0.0, &due, &due_times_s);
  clocks.TakeDue(0.050, &due, &due_times_s);  // a 50 ms stall
  ASSERT_EQ(due.size(), 2u);
  EXPECT_EQ(clocks.reanchors(), 2u);
  EXPECT_DOUBLE_EQ(clocks.NextDueS(), 0.050);  // next tick now, then one per period again
  clocks.TakeDue(0.050, &due, &due_times_s);
  EXPECT_EQ(due.size(), 2u);
  EXPECT_NEAR(clocks.NextDueS(), 0.051, 1e-12);
}

// The servo thread that wakes late for the run's last tick (here 1.2 ms
// late, 0.4 ms past a 10 ms end) steps only the devices due before the end:
// a tick that falls after the end is not taken, so no device sends an extra
// pose.
TEST(DeviceClocks, AWakePastTheRunsEndTakesOnlyTheTicksDueBeforeIt) {
  const double end_s = 0.010;
  DeviceClocks clocks({0.0, 2e-4}, {0.0, 0.0}, 1e-3, end_s);
  std::vector<std::size_t> due;
  std::vector<double> due_times_s;
  due.reserve(2);
  due_times_s.reserve(2);
  std::vector<std::uint64_t> ticks(2, 0);
  for (double next_s = clocks.NextDueS(); next_s < end_s; next_s = clocks.NextDueS()) {
    // On time, except for device 1's last tick (9.2 ms): woken at 10.4 ms, past device 0's 10 ms tick.
    const double now_s = next_s > 9.1e-3 ? next_s + 1.2e-3 : next_s;
    clocks.TakeDue(now_s, &due, &due_times_s);
    for (const std::size_t i : due) ++ticks[i];
  }
  EXPECT_EQ(ticks[0], 10u);  // 0, 1, ..., 9 ms; 10 ms is the end
  EXPECT_EQ(ticks[1], 10u);  // 0.2, 1.2, ..., 9.2 ms
  EXPECT_EQ(clocks.reanchors(), 0u);
}

}  // namespace
}  // namespace hapsim::bridge
