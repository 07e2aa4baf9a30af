#include "hapsim/bridge/servo_loop.h"

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <thread>

#include "hapsim/runtime/clock.h"

namespace hapsim::bridge {

core::LocalForceModel ToCoreModel(const hapsim_dds_LocalForceModel& m) {
  core::LocalForceModel c;
  c.state = m.state <= 3 ? static_cast<core::ContactState>(m.state) : core::ContactState::kFree;
  c.anchor_W_m = {m.anchor_m[0], m.anchor_m[1], m.anchor_m[2]};
  c.normal_W = {m.normal[0], m.normal[1], m.normal[2]};
  c.stiffness_N_per_m = m.stiffness_n_per_m;
  c.damping_Ns_per_m = m.damping_ns_per_m;
  c.feedforward_W_N = {m.feedforward_n[0], m.feedforward_n[1], m.feedforward_n[2]};
  return c;
}

ServoLoop::ServoLoop(HapticDevice* device, ServoConfig config,
                     runtime::LatestValue<hapsim_dds_StylusPose>* pose_out,
                     runtime::LatestValue<ReceivedModel>* model_in, std::function<void()> wake_io)
    : device_(device), config_(std::move(config)), pose_out_(pose_out), model_in_(model_in), wake_io_(std::move(wake_io)) {}

ServoReport ServoLoop::Run(const std::atomic<bool>& stop) {
  using clock = std::chrono::steady_clock;
  ServoReport report;
  report.trace.reserve(config_.trace_capacity);
  ForceSafety safety(config_.safety);
  runtime::SampleWindow period_error(1 << 17), model_age(1 << 17), round_trip(1 << 17);

  // Send time of each pose by seq, to turn an echoed seq into a round trip.
  constexpr std::size_t kRing = 4096;
  std::array<std::uint64_t, kRing> sent_seq{};
  std::array<std::int64_t, kRing> sent_ns{};
  sent_seq.fill(~0ull);

  const double dt = 1.0 / config_.rate_hz;
  const auto period = std::chrono::duration_cast<clock::duration>(std::chrono::duration<double>(dt));
  const auto start = clock::now();
  auto next = start;
  auto previous_wake = start;
  std::uint64_t seq = 0;
  bool have_model = false, have_echo = false;
  ReceivedModel model;
  core::LocalForceModel local;
  hapsim_dds_StylusPose pose{};
  pose.device_id = config_.device_id;
  std::strncpy(pose.session, config_.session.c_str(), sizeof pose.session - 1);

  while (!stop.load(std::memory_order_relaxed)) {
    std::this_thread::sleep_until(next);
    const auto wake = clock::now();
    const double t = std::chrono::duration<double>(wake - start).count();
    if (config_.run_seconds > 0.0 && t >= config_.run_seconds) break;
    if (report.ticks > 0) period_error.Record(std::abs(std::chrono::duration<double>(wake - previous_wake).count() - dt));
    previous_wake = wake;

    // 1. device -> pose mailbox (the DDS thread sends it)
    const DeviceReading reading = device_->Read(t);
    if (reading.finished && config_.stop_when_script_finishes) break;
    const std::int64_t now_ns = runtime::SteadyNowNs();
    pose.seq = seq;
    pose.t_device_ns = now_ns;
    for (int k = 0; k < 3; ++k) {
      pose.pos_m[k] = reading.tip_W_m[k];
      pose.vel_m_per_s[k] = reading.velocity_W_m_per_s[k];
    }
    pose.quat_wxyz[0] = reading.orientation_W.w();
    pose.quat_wxyz[1] = reading.orientation_W.x();
    pose.quat_wxyz[2] = reading.orientation_W.y();
    pose.quat_wxyz[3] = reading.orientation_W.z();
    pose.buttons = reading.buttons;
    sent_seq[seq % kRing] = seq;
    sent_ns[seq % kRing] = now_ns;
    ++seq;
    pose_out_->Publish(pose);
    wake_io_();

    // 2. newest force model
    if (model_in_->TakeIfNew(&model)) {
      ++report.models_received;
      const std::uint64_t echo = model.msg.echo_pose_seq;
      if (have_echo && echo < report.last_echo_seq) ++report.echo_regressions;
      if (!have_echo) report.first_echo_seq = echo;
      report.last_echo_seq = echo;
      have_echo = true;
      if (sent_seq[echo % kRing] == echo) {
        round_trip.Record(static_cast<double>(model.received_ns - sent_ns[echo % kRing]) * 1e-9);
      }
      local = ToCoreModel(model.msg);
      have_model = true;
    }
    // A model can land between the clock read above and the take: age 0, not
    // negative (negative means "no model" to the safety layer).
    const double age_s = have_model ? std::max(0.0, static_cast<double>(now_ns - model.received_ns) * 1e-9) : -1.0;
    if (have_model) model_age.Record(age_s);

    // 3. force: local model -> safety -> device
    const Eigen::Vector3d requested =
        have_model ? core::EvaluateLocalForce(local, reading.tip_W_m, reading.velocity_W_m_per_s)
                   : Eigen::Vector3d::Zero();
    const Eigen::Vector3d force = safety.Apply(requested, age_s, dt);
    device_->CommandForce(force);

    // 4. bookkeeping
    const double magnitude = force.norm();
    report.peak_force_N = std::max(report.peak_force_N, magnitude);
    const std::string_view phase = reading.phase;
    if (phase == "press" || phase == "hold") report.peak_force_pressing_N = std::max(report.peak_force_pressing_N, magnitude);
    if (phase == "withdraw" && reading.tip_W_m.z() > 0.001) {
      report.peak_force_withdrawn_N = std::max(report.peak_force_withdrawn_N, magnitude);
    }
    if (report.trace.size() < config_.trace_capacity) {
      report.trace.push_back({t, reading.tip_W_m, reading.orientation_W, force, requested, age_s * 1e3,
                              have_echo ? report.last_echo_seq : 0, reading.phase,
                              have_model ? model.msg.state : std::uint8_t{0}, safety.state()});
    }
    ++report.ticks;
    next += period;
    if (clock::now() - next > 10 * period) next = clock::now();  // stalled: re-anchor
  }
  report.elapsed_s = std::chrono::duration<double>(clock::now() - start).count();
  report.period_error_s = period_error.Summary();
  report.model_age_s = model_age.Summary();
  report.round_trip_s = round_trip.Summary();
  report.safety = safety.counters();
  return report;
}

bool WriteTraceCsv(const std::string& path, const std::vector<TraceRow>& rows) {
  std::FILE* f = std::fopen(path.c_str(), "w");
  if (!f) return false;
  std::fprintf(f, "t_s,x_m,y_m,z_m,qw,qx,qy,qz,fx_N,fy_N,fz_N,req_fx_N,req_fy_N,req_fz_N,model_age_ms,"
                  "echo_pose_seq,model_state,watchdog,phase\n");
  for (const auto& r : rows) {
    std::fprintf(f, "%.6f,%.9f,%.9f,%.9f,%.9f,%.9f,%.9f,%.9f,%.6f,%.6f,%.6f,%.6f,%.6f,%.6f,%.3f,%llu,%u,%s,%s\n",
                 r.t_s, r.tip_W_m.x(), r.tip_W_m.y(), r.tip_W_m.z(), r.orientation_W.w(), r.orientation_W.x(),
                 r.orientation_W.y(), r.orientation_W.z(), r.force_W_N.x(), r.force_W_N.y(), r.force_W_N.z(),
                 r.requested_W_N.x(), r.requested_W_N.y(), r.requested_W_N.z(), r.model_age_ms,
                 static_cast<unsigned long long>(r.echo_pose_seq), static_cast<unsigned>(r.model_state),
                 ToString(r.watchdog), r.phase);
  }
  return std::fclose(f) == 0;
}

}  // namespace hapsim::bridge
