#include "hapsim/load/load_runner.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <thread>

#include "hapsim/common/clock.h"
#include "hapsim/servo/deadline_ticker.h"

namespace hapsim::bridge {

namespace {
constexpr std::size_t kPooledSampleBudget = std::size_t{1} << 22;  // per statistic: 32 MiB of doubles
constexpr std::size_t kMinWindow = 1024;
// Interval percentiles: 1 us .. 100 s in bins 2 % wide (~930 bins each).
constexpr double kIntervalLowestS = 1e-6, kIntervalHighestS = 100.0, kIntervalBinRatio = 1.02;
// Intervals kept when the run has no end: a day of 10 s intervals.
constexpr std::size_t kUnboundedIntervals = 8640;

std::size_t IntervalsToReserve(const LoadRunConfig& c) {
  if (c.interval_s <= 0.0) return 0;
  if (c.run_seconds <= 0.0) return kUnboundedIntervals;
  return static_cast<std::size_t>(std::ceil(c.run_seconds / c.interval_s)) + 2;
}
}  // namespace

std::size_t StatsWindowPerDevice(double run_seconds, double rate_hz, std::size_t devices) {
  const std::size_t wanted =
      run_seconds > 0.0 ? static_cast<std::size_t>(std::ceil(run_seconds * rate_hz * 1.05)) + 16 : std::size_t{1} << 16;
  const std::size_t budget = kPooledSampleBudget / std::max<std::size_t>(devices, 1);
  return std::max(kMinWindow, std::min(wanted, budget));
}

LoadRunner::LoadRunner(const std::vector<LoadDevicePlan>& plan, const LoadRunConfig& config, ModelRouter* router,
                       PoseWriter write_pose)
    : config_(config),
      router_(router),
      write_pose_(std::move(write_pose)),
      plan_(plan),
      poses_sent_(plan.size(), 0),
      write_failures_(plan.size(), 0),
      pooled_round_trip_s_(StatsWindowPerDevice(config.run_seconds, config.rate_hz, plan.size()) * plan.size()),
      pooled_model_age_s_(StatsWindowPerDevice(config.run_seconds, config.rate_hz, plan.size()) * plan.size()),
      pooled_physics_age_s_(StatsWindowPerDevice(config.run_seconds, config.rate_hz, plan.size()) * plan.size()),
      interval_round_trip_s_(kIntervalLowestS, kIntervalHighestS, kIntervalBinRatio),
      interval_model_age_s_(kIntervalLowestS, kIntervalHighestS, kIntervalBinRatio),
      interval_end_s_(config.interval_s) {
  intervals_.reserve(IntervalsToReserve(config_));
  ChannelConfig c;
  c.period_s = 1.0 / config_.rate_hz;
  c.safety = config_.safety;
  c.pose_deadband = config_.pose_deadband;
  c.stats_window = StatsWindowPerDevice(config_.run_seconds, config_.rate_hz, plan_.size());
  devices_.reserve(plan_.size());
  channels_.reserve(plan_.size());
  for (const auto& p : plan_) {
    devices_.push_back(std::make_unique<SyntheticDevice>(p.script));
    c.device_id = p.device_id;
    channels_.emplace_back(devices_.back().get(), c);
  }
}

void LoadRunner::StepDevice(std::size_t i, double t_s) {
  ServoChannel& channel = channels_[i];
  channel.Sense(t_s + plan_[i].phase_s);
  if (channel.pose_due()) {  // else held back by the pose deadband
    if (write_pose_(channel.pose())) {
      ++poses_sent_[i];
    } else {
      ++write_failures_[i];
    }
  }
  const ChannelTick& tick = channel.Actuate(router_->inbox(i));
  if (tick.round_trip_s >= 0.0) {
    pooled_round_trip_s_.Record(tick.round_trip_s);
    interval_round_trip_s_.Record(tick.round_trip_s);
  }
  if (tick.model_age_s >= 0.0) {
    pooled_model_age_s_.Record(tick.model_age_s);
    interval_model_age_s_.Record(tick.model_age_s);
  }
  if (std::isfinite(tick.physics_age_s) && tick.physics_age_s >= 0.0) pooled_physics_age_s_.Record(tick.physics_age_s);
}

void LoadRunner::CloseInterval(double end_s) {
  if (intervals_.size() < intervals_.capacity()) {
    intervals_.push_back({end_s, interval_round_trip_s_.Summary(), interval_model_age_s_.Summary()});
  } else {
    ++intervals_dropped_;
  }
  interval_round_trip_s_.Clear();
  interval_model_age_s_.Clear();
}

void LoadRunner::CloseIntervalIfEnded(double t_s) {
  if (config_.interval_s > 0.0 && t_s >= interval_end_s_) {
    CloseInterval(interval_end_s_);
    interval_end_s_ += config_.interval_s;
  }
}

void LoadRunner::RunInLockstep(const std::atomic<bool>& stop, ServoThreadReport* servo) {
  DeadlineTicker ticker(config_.rate_hz, StatsWindowPerDevice(config_.run_seconds, config_.rate_hz, 1));
  common::SampleWindow work_s(StatsWindowPerDevice(config_.run_seconds, config_.rate_hz, 1));
  while (!stop.load(std::memory_order_relaxed)) {
    const double t = ticker.Wait();
    if (config_.run_seconds > 0.0 && t >= config_.run_seconds) break;
    CloseIntervalIfEnded(t);
    const std::int64_t start_ns = common::SteadyNowNs();
    for (std::size_t i = 0; i < channels_.size(); ++i) StepDevice(i, t);
    work_s.Record(static_cast<double>(common::SteadyNowNs() - start_ns) * 1e-9);
  }
  servo->ticks = work_s.Total();
  servo->reanchors = ticker.reanchors();
  servo->lateness_s = ticker.Lateness();
  servo->work_s = work_s.Summary();
}

void LoadRunner::RunOnDeviceClocks(const std::atomic<bool>& stop, ServoThreadReport* servo) {
  std::vector<double> phases_s, rates_ppm;
  for (const auto& p : plan_) {
    phases_s.push_back(p.clock_phase_s);
    rates_ppm.push_back(p.clock_rate_ppm);
  }
  // A wake late past the end must not step devices whose next tick is after it.
  DeviceClocks clocks(phases_s, rates_ppm, 1.0 / config_.rate_hz,
                      config_.run_seconds > 0.0 ? config_.run_seconds : std::numeric_limits<double>::infinity());
  // One wake per device tick at most: a window of the run's wakes for every device.
  const std::size_t window =
      std::min(StatsWindowPerDevice(config_.run_seconds, config_.rate_hz, 1) * plan_.size(), kPooledSampleBudget);
  common::SampleWindow work_s(window), lateness_s(window);
  std::vector<std::size_t> due;
  std::vector<double> due_times_s;
  due.reserve(plan_.size());
  due_times_s.reserve(plan_.size());
  const auto start = std::chrono::steady_clock::now();
  const auto since_start_s = [&] {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  };
  while (!stop.load(std::memory_order_relaxed)) {
    const double next_s = clocks.NextDueS();
    if (config_.run_seconds > 0.0 && next_s >= config_.run_seconds) break;
    std::this_thread::sleep_until(
        start + std::chrono::duration_cast<std::chrono::steady_clock::duration>(std::chrono::duration<double>(next_s)));
    const double now_s = since_start_s();
    lateness_s.Record(now_s - next_s);
    CloseIntervalIfEnded(now_s);
    const std::int64_t start_ns = common::SteadyNowNs();
    clocks.TakeDue(now_s, &due, &due_times_s);
    for (std::size_t k = 0; k < due.size(); ++k) StepDevice(due[k], due_times_s[k]);
    work_s.Record(static_cast<double>(common::SteadyNowNs() - start_ns) * 1e-9);
  }
  servo->ticks = work_s.Total();
  servo->reanchors = clocks.reanchors();
  servo->lateness_s = lateness_s.Summary();
  servo->work_s = work_s.Summary();
}

LoadReport LoadRunner::Run(const std::atomic<bool>& stop) {
  const auto start = std::chrono::steady_clock::now();
  ServoThreadReport servo;
  if (HasOwnClocks(plan_)) {
    RunOnDeviceClocks(stop, &servo);
  } else {
    RunInLockstep(stop, &servo);
  }
  for (auto& device : devices_) device->CommandForce(Eigen::Vector3d::Zero());  // leave the motors off
  const double elapsed_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  if (config_.interval_s > 0.0 && interval_round_trip_s_.count() + interval_model_age_s_.count() > 0) {
    CloseInterval(std::min(elapsed_s, interval_end_s_));  // the last, shorter one
  }
  LoadReport report = Report(elapsed_s);
  report.servo = servo;
  return report;
}

LoadReport LoadRunner::Report(double elapsed_s) const {
  LoadReport r;
  r.rate_hz = config_.rate_hz;
  r.elapsed_s = elapsed_s;
  r.devices.resize(channels_.size());
  for (std::size_t i = 0; i < channels_.size(); ++i) {
    const ServoChannel& ch = channels_[i];
    const ChannelCounters& c = ch.counters();
    LoadDeviceReport& d = r.devices[i];
    d.device_id = plan_[i].device_id;
    d.session = plan_[i].session;
    d.flow.poses_sent = poses_sent_[i];
    d.flow.pose_write_failures = write_failures_[i];
    d.flow.pose_rate_hz = elapsed_s > 0.0 ? static_cast<double>(poses_sent_[i]) / elapsed_s : 0.0;
    d.flow.models_received = router_->models_routed(i);
    d.flow.models_used = c.models_taken;
    d.flow.echo_regressions = c.echo_regressions;
    d.flow.models_unused = c.models_unused;
    d.flow.round_trip_s = ch.RoundTrip();
    d.flow.model_age_s = ch.ModelAge();
    d.flow.physics_age_s = ch.PhysicsAge();
    d.flow.safety = ch.safety_counters();
    d.first_echo_seq = c.first_echo_seq;
    d.last_echo_seq = c.last_echo_seq;
    d.final_watchdog = ch.watchdog();
    d.peak_force_N = c.peak_force_N;
  }
  r.total = SumDevices(r.devices);
  r.total.flow.round_trip_s = pooled_round_trip_s_.Summary();
  r.total.flow.model_age_s = pooled_model_age_s_.Summary();
  r.total.flow.physics_age_s = pooled_physics_age_s_.Summary();
  r.models_for_unknown_devices = router_->models_for_unknown_devices();
  r.models_for_other_sessions = router_->models_for_other_sessions();
  for (std::size_t i = 0; i < router_->devices(); ++i)
    r.models_from_other_servers += router_->models_from_other_servers(i);
  r.intervals = intervals_;
  r.intervals_dropped = intervals_dropped_;
  return r;
}

}  // namespace hapsim::bridge
