#include "hapsim/servo/servo_loop.h"

#include <chrono>
#include <cmath>
#include <cstdio>
#include <limits>

#include "hapsim/servo/deadline_ticker.h"

namespace hapsim::bridge {
namespace {
const Eigen::Vector3d kUnknownForce_W_N = Eigen::Vector3d::Constant(std::numeric_limits<double>::quiet_NaN());
}  // namespace

ServoLoop::ServoLoop(HapticDevice* device, ServoConfig config, common::LatestValue<SensedPose>* pose_out,
                     common::LatestValue<ReceivedModel>* model_in, std::function<void()> wake_io)
    : device_(device),
      config_(std::move(config)),
      pose_out_(pose_out),
      model_in_(model_in),
      wake_io_(std::move(wake_io)) {}

ServoReport ServoLoop::Run(const std::atomic<bool>& stop) {
  ServoReport report;
  report.trace.reserve(config_.trace_capacity);
  ChannelConfig channel_config;
  channel_config.device_id = config_.device_id;
  channel_config.period_s = 1.0 / config_.rate_hz;
  channel_config.safety = config_.safety;
  channel_config.model_delay_s = config_.model_delay_s;
  channel_config.pose_deadband = config_.pose_deadband;
  channel_config.physics_reference = config_.trace_capacity > 0;  // only the trace reads it
  ServoChannel channel(device_, channel_config);
  if (device_->RunsOwnServo()) {
    RunOnDeviceServo(channel, stop, &report);
  } else {
    RunOnTicker(channel, stop, &report);
  }
  report.model_age_s = channel.ModelAge();
  report.physics_age_s = channel.PhysicsAge();
  report.round_trip_s = channel.RoundTrip();
  report.channel = channel.counters();
  report.safety = channel.safety_counters();
  report.final_watchdog = channel.watchdog();
  return report;
}

void ServoLoop::RunOnTicker(ServoChannel& channel, const std::atomic<bool>& stop, ServoReport* report) {
  DeadlineTicker ticker(config_.rate_hz);
  while (!stop.load(std::memory_order_relaxed)) {
    if (!Tick(channel, ticker.Wait(), stop, report)) break;
  }
  report->elapsed_s = ticker.ElapsedS();
  report->period_error_s = ticker.PeriodError();
}

// The device's scheduler is the clock: the period error is measured from
// the times it passes to successive ticks.
void ServoLoop::RunOnDeviceServo(ServoChannel& channel, const std::atomic<bool>& stop, ServoReport* report) {
  const double period_s = 1.0 / config_.rate_hz;
  common::SampleWindow period_error_s(1 << 17);
  double previous_t_s = -1.0;
  const auto start = std::chrono::steady_clock::now();
  // Built once, before the first tick (a std::function may allocate).
  const std::function<bool(double)> tick = [&](double t_s) {
    if (!Tick(channel, t_s, stop, report)) return false;
    if (previous_t_s >= 0.0) period_error_s.Record(std::abs(t_s - previous_t_s - period_s));
    previous_t_s = t_s;
    return true;
  };
  device_->RunServo(tick, stop);
  report->elapsed_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  report->period_error_s = period_error_s.Summary();
}

bool ServoLoop::Tick(ServoChannel& channel, double t, const std::atomic<bool>& stop, ServoReport* report) {
  if (stop.load(std::memory_order_relaxed)) return false;
  if (config_.run_seconds > 0.0 && t >= config_.run_seconds) return false;
  // 1. device -> pose mailbox (the DDS thread sends it)
  const DeviceReading& reading = channel.Sense(t);
  if (reading.finished && config_.stop_when_script_finishes) return false;
  if (channel.pose_due()) {
    pose_out_->Publish(channel.pose());
    wake_io_();
  }
  // 2. newest model -> safety -> device
  const ChannelTick& tick = channel.Actuate(*model_in_);
  if (tick.took_model && report->first_model_s < 0.0) report->first_model_s = t;
  // 3. trace (reserved before the loop: no allocation)
  if (report->trace.size() < config_.trace_capacity) {
    const ChannelCounters& c = channel.counters();
    report->trace.push_back({t, reading.tip_W_m, reading.orientation_W, tick.force_W_N, tick.requested_W_N,
                             tick.model_age_s * 1e3, tick.physics_age_s * 1e3, c.models_taken > 0 ? c.last_echo_seq : 0,
                             reading.phase, static_cast<std::uint8_t>(channel.model_state()), channel.watchdog(),
                             channel.pose().seq, channel.pose_due(), tick.took_model, kUnknownForce_W_N});
  }
  // The physics' answer to an earlier tick's pose goes into that tick's row.
  if (tick.round_trip_s >= 0.0 && !report->trace.empty()) {
    const std::uint64_t first = report->trace.front().pose_seq;
    const std::uint64_t echo = channel.counters().last_echo_seq;
    if (echo >= first && echo - first < report->trace.size()) {
      report->trace[echo - first].physics_W_N = tick.physics_at_echo_W_N;
    }
  }
  return true;
}

bool WriteTraceCsv(const std::string& path, const std::vector<TraceRow>& rows) {
  std::FILE* f = std::fopen(path.c_str(), "w");
  if (!f) return false;
  std::fprintf(f,
               "t_s,x_m,y_m,z_m,qw,qx,qy,qz,fx_N,fy_N,fz_N,req_fx_N,req_fy_N,req_fz_N,model_age_ms,"
               "echo_pose_seq,model_state,watchdog,phase,pose_seq,phys_fx_N,phys_fy_N,phys_fz_N,pose_sent,model_taken,"
               "physics_age_ms\n");
  for (const auto& r : rows) {
    // t_s to the nanosecond: after a late tick the servo catches up with
    // wakes microseconds apart, which 6 decimals would write as one time
    // (and the replay backend needs them increasing).
    std::fprintf(f,
                 "%.9f,%.9f,%.9f,%.9f,%.9f,%.9f,%.9f,%.9f,%.6f,%.6f,%.6f,%.6f,%.6f,%.6f,%.3f,%llu,%u,%s,%s,%llu,%.6f,%."
                 "6f,%.6f,%d,%d,%.3f\n",
                 r.t_s, r.tip_W_m.x(), r.tip_W_m.y(), r.tip_W_m.z(), r.orientation_W.w(), r.orientation_W.x(),
                 r.orientation_W.y(), r.orientation_W.z(), r.force_W_N.x(), r.force_W_N.y(), r.force_W_N.z(),
                 r.requested_W_N.x(), r.requested_W_N.y(), r.requested_W_N.z(), r.model_age_ms,
                 static_cast<unsigned long long>(r.echo_pose_seq), static_cast<unsigned>(r.model_state),
                 ToString(r.watchdog), r.phase, static_cast<unsigned long long>(r.pose_seq), r.physics_W_N.x(),
                 r.physics_W_N.y(), r.physics_W_N.z(), r.pose_sent ? 1 : 0, r.model_taken ? 1 : 0, r.physics_age_ms);
  }
  return std::fclose(f) == 0;
}

}  // namespace hapsim::bridge
