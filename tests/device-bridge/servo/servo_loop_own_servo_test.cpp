// A device whose driver runs its own servo scheduler (OpenHaptics) drives
// the loop: each of its ticks is one servo tick at the time it passes, the
// period error is measured between successive times, and the loop ends when
// run_seconds is reached (the tick returns false) or stop is set.
#include <gtest/gtest.h>

#include <atomic>
#include <vector>

#include "hapsim/servo/servo_loop.h"

// Its own namespace: the test files are compiled in batches (unity build).
namespace hapsim::bridge::servo_loop_own_servo_test {
namespace {

// Calls tick at the times it is given, without sleeping, until tick
// returns false, stop is set or the times run out.
class SchedulerDevice final : public HapticDevice {
 public:
  explicit SchedulerDevice(std::vector<double> times_s) : times_s_(std::move(times_s)) {}
  std::string Name() const override { return "scheduler"; }
  DeviceReading Read(double t_s) override {
    read_times_s.push_back(t_s);
    DeviceReading r;
    r.tip_W_m = Eigen::Vector3d(0, 0, -0.002);
    return r;
  }
  void CommandForce(const Eigen::Vector3d& force_W_N) override { forces_W_N.push_back(force_W_N); }
  bool RunsOwnServo() const override { return true; }
  void RunServo(const std::function<bool(double)>& tick, const std::atomic<bool>& stop) override {
    ++runs;
    for (const double t_s : times_s_) {
      if (stop.load() || !tick(t_s)) return;
      if (t_s >= stop_after_s) stop_flag->store(true);
    }
  }

  int runs = 0;
  std::vector<double> read_times_s;
  std::vector<Eigen::Vector3d> forces_W_N;
  double stop_after_s = 1e9;
  std::atomic<bool>* stop_flag = nullptr;

 private:
  std::vector<double> times_s_;
};

struct Loop {
  common::LatestValue<SensedPose> poses;
  common::LatestValue<ReceivedModel> models;
  ServoReport Run(HapticDevice* device, ServoConfig config, std::atomic<bool>* stop) {
    ServoLoop loop(device, config, &poses, &models, [] {});
    return loop.Run(*stop);
  }
};

// 250 ticks offered exactly 1 ms apart, run_seconds 0.2: the ticks at
// t = 0 ... 0.199 s run (200), the one at 0.2 s ends the loop; 199 period
// errors, each |1 ms - 1 ms| (to 1e-12 s).
TEST(OwnServo, TheDevicesSchedulerIsTheClockUntilRunSeconds) {
  std::vector<double> times_s;
  for (int k = 0; k < 250; ++k) times_s.push_back(k * 0.001);
  SchedulerDevice device(times_s);
  ServoConfig config;
  config.run_seconds = 0.2;
  config.trace_capacity = 1000;
  std::atomic<bool> stop{false};
  Loop loop;
  const ServoReport r = loop.Run(&device, config, &stop);
  EXPECT_EQ(device.runs, 1);
  EXPECT_EQ(r.channel.ticks, 200u);
  ASSERT_EQ(r.trace.size(), 200u);
  ASSERT_EQ(device.read_times_s.size(), 200u);
  EXPECT_EQ(device.forces_W_N.size(), 200u);
  for (int k = 0; k < 200; ++k) {
    ASSERT_EQ(r.trace[k].t_s, k * 0.001);
    ASSERT_EQ(device.read_times_s[k], k * 0.001);
  }
  EXPECT_EQ(r.period_error_s.count, 199u);
  EXPECT_LE(r.period_error_s.max, 1e-12);
  EXPECT_EQ(r.safety.disarms, 0u);
  EXPECT_EQ(r.final_watchdog, WatchdogState::kNoModel);  // no model came: the force stayed zero
  for (const auto& f : device.forces_W_N) ASSERT_EQ(f.norm(), 0.0);
}

// A scheduler alternating 0.9 and 1.1 ms periods: every period error is
// 0.1 ms (to 1e-12 s).
TEST(OwnServo, ThePeriodErrorComesFromSuccessiveTickTimes) {
  std::vector<double> times_s{0.0};
  for (int k = 1; k < 100; ++k) times_s.push_back(times_s.back() + (k % 2 ? 0.0009 : 0.0011));
  SchedulerDevice device(times_s);
  std::atomic<bool> stop{false};
  Loop loop;
  const ServoReport r = loop.Run(&device, ServoConfig{}, &stop);
  EXPECT_EQ(r.channel.ticks, 100u);
  EXPECT_EQ(r.period_error_s.count, 99u);
  EXPECT_NEAR(r.period_error_s.min, 1e-4, 1e-12);
  EXPECT_NEAR(r.period_error_s.max, 1e-4, 1e-12);
}

// stop set (from another thread, here by the device after its 10th tick)
// ends the run at the next tick.
TEST(OwnServo, StopEndsTheRun) {
  std::vector<double> times_s;
  for (int k = 0; k < 100; ++k) times_s.push_back(k * 0.001);
  SchedulerDevice device(times_s);
  std::atomic<bool> stop{false};
  device.stop_flag = &stop;
  device.stop_after_s = 0.009;
  Loop loop;
  const ServoReport r = loop.Run(&device, ServoConfig{}, &stop);
  EXPECT_EQ(r.channel.ticks, 10u);
}

}  // namespace
}  // namespace hapsim::bridge::servo_loop_own_servo_test
