// hapsim-bridge: the device-bridge process. Reads a haptic device at 1 kHz
// (synthetic or replay backends here; OpenHaptics when built with the SDK),
// streams its pose over DDS, and renders the server's local force model,
// clamped and watched by the staleness watchdog. Prints a summary at exit.
#include <atomic>
#include <cmath>
#include <cstdio>
#include <memory>
#include <thread>

#include <asio/io_context.hpp>
#include <asio/signal_set.hpp>
#include <spdlog/spdlog.h>

#include "backends/replay_device.h"
#include "backends/synthetic_device.h"
#include "hapsim/bridge/bridge_dds.h"
#include "hapsim/bridge/servo_loop.h"
#include "hapsim/runtime/flags.h"
#include "hapsim/runtime/logging.h"

namespace {

void PrintReport(const hapsim::bridge::ServoReport& r, const std::string& device, const std::string& session,
                 const hapsim::bridge::BridgeDds& dds, const std::string& watchdog_state) {
  using hapsim::runtime::FormatPercentiles;
  std::printf("bridge: device %s, session %s\n", device.c_str(), session.c_str());
  std::printf("bridge: loop %.1f Hz over %.2f s (%llu ticks)\n", r.elapsed_s > 0 ? r.ticks / r.elapsed_s : 0.0,
              r.elapsed_s, static_cast<unsigned long long>(r.ticks));
  std::printf("bridge: period jitter %s\n", FormatPercentiles(r.period_error_s, 1e3, "ms").c_str());
  std::printf("bridge: poses sent %llu; force models received %llu (echoed pose seq %llu -> %llu, regressions %llu)\n",
              static_cast<unsigned long long>(dds.poses_written()), static_cast<unsigned long long>(r.models_received),
              static_cast<unsigned long long>(r.first_echo_seq), static_cast<unsigned long long>(r.last_echo_seq),
              static_cast<unsigned long long>(r.echo_regressions));
  std::printf("bridge: round trip %s\n", FormatPercentiles(r.round_trip_s, 1e3, "ms").c_str());
  std::printf("bridge: model age %s\n", FormatPercentiles(r.model_age_s, 1e3, "ms").c_str());
  std::printf("bridge: force peak %.3f N (pressing %.3f N, withdrawn %.3f N)\n", r.peak_force_N,
              r.peak_force_pressing_N, r.peak_force_withdrawn_N);
  std::printf("bridge: safety clamped %llu, rise-limited %llu, non-finite %llu, disarms %llu, watchdog %s\n",
              static_cast<unsigned long long>(r.safety.clamped), static_cast<unsigned long long>(r.safety.rate_limited),
              static_cast<unsigned long long>(r.safety.non_finite), static_cast<unsigned long long>(r.safety.disarms),
              watchdog_state.c_str());
  std::fflush(stdout);
}

}  // namespace

int main(int argc, char** argv) {
  std::string session = "demo", backend = "synthetic", replay_file, trace_file, log_level = "info", dds_config;
  int device_id = 1, dds_domain = 0, seed = 1;
  double seconds = 0.0, rate_hz = 1000.0;
  hapsim::bridge::SyntheticScript script;
  double depth_mm = 5.0, speed_mm_s = 10.0, start_height_mm = 10.0, entry_x_mm = 0.0, entry_y_mm = 0.0;
  hapsim::bridge::SafetyConfig safety;
  double warn_ms = 20.0, fade_ms = 50.0, disarm_ms = 100.0;
  bool keep_running = false;

  hapsim::runtime::Flags flags(
      "hapsim-bridge",
      "Device-bridge of hapsim: reads a haptic device at the servo rate, publishes its pose over DDS,\n"
      "and renders the physics server's local force model with a force clamp, a rise-rate limit and a\n"
      "staleness watchdog. Backends: synthetic (scripted motion), replay (pose log CSV).");
  flags.Add("session", &session, "session id to drive");
  flags.Add("device-id", &device_id, "device id (unique per device on the DDS domain)");
  flags.Add("backend", &backend, "synthetic or replay");
  flags.Add("script", &script.kind, "synthetic script: insertion, constant_speed, random_walk or hold");
  flags.Add("depth-mm", &depth_mm, "synthetic: deepest tip position below the surface [mm]");
  flags.Add("speed-mm-s", &speed_mm_s, "synthetic: tip speed [mm/s]");
  flags.Add("start-height-mm", &start_height_mm, "synthetic: height above the surface where motion starts [mm]");
  flags.Add("hold-s", &script.hold_s, "synthetic insertion: time held at depth [s]");
  flags.Add("entry-x-mm", &entry_x_mm, "synthetic: x of the entry point on the surface [mm]");
  flags.Add("entry-y-mm", &entry_y_mm, "synthetic: y of the entry point on the surface [mm]");
  flags.Add("seed", &seed, "synthetic random_walk: seed");
  flags.Add("replay-file", &replay_file, "replay: pose log CSV (t_s,x_m,y_m,z_m,qw,qx,qy,qz,...)");
  flags.Add("seconds", &seconds, "stop after this long [s] (0: until SIGINT/SIGTERM)");
  flags.Add("keep-running", &keep_running, "keep running after a finite script or replay ends");
  flags.Add("rate-hz", &rate_hz, "servo loop rate [Hz]");
  flags.Add("max-force-n", &safety.max_force_N, "force clamp [N] (Phantom Omni peak: 3.3 N)");
  flags.Add("max-force-rise-n-per-s", &safety.max_rise_N_per_s, "largest rise of the force magnitude [N/s]");
  flags.Add("watchdog-warn-ms", &warn_ms, "model older than this: warning [ms]");
  flags.Add("watchdog-fade-ms", &fade_ms, "model older than this: force fades out [ms]");
  flags.Add("watchdog-disarm-ms", &disarm_ms, "model older than this: zero force until a fresh model [ms]");
  flags.Add("trace", &trace_file, "write a per-tick CSV trace here (first 10 minutes; replayable)");
  flags.Add("dds-domain", &dds_domain, "DDS domain id");
  flags.Add("dds-config", &dds_config, "Cyclone DDS config file (default: CYCLONEDDS_URI if set, else built-in loopback)");
  flags.Add("log-level", &log_level, "trace, debug, info, warn, error or off");
  std::string error;
  switch (flags.Parse(argc, argv, &error)) {
    case hapsim::runtime::Flags::Result::kHelp: std::fputs(flags.Help().c_str(), stdout); return 0;
    case hapsim::runtime::Flags::Result::kError: std::fprintf(stderr, "hapsim-bridge: %s\n", error.c_str()); return 2;
    case hapsim::runtime::Flags::Result::kOk: break;
  }
  if (!hapsim::runtime::SetUpLogging("bridge", log_level)) {
    std::fprintf(stderr, "hapsim-bridge: unknown --log-level '%s'\n", log_level.c_str());
    return 2;
  }
  if (!(rate_hz >= 100.0 && rate_hz <= 10000.0) || !(seconds >= 0.0) || device_id < 0 || dds_domain < 0 ||
      dds_domain > 232 || session.empty() || session.size() > 63) {
    std::fprintf(stderr, "hapsim-bridge: a flag is out of range (see --help)\n");
    return 2;
  }
  safety.warn_age_s = warn_ms * 1e-3;
  safety.fade_start_age_s = fade_ms * 1e-3;
  safety.disarm_age_s = disarm_ms * 1e-3;

  try {
    hapsim::bridge::ValidateSafetyConfig(safety);
    std::unique_ptr<hapsim::bridge::HapticDevice> device;
    if (backend == "synthetic") {
      script.depth_m = depth_mm * 1e-3;
      script.speed_m_per_s = speed_mm_s * 1e-3;
      script.start_height_m = start_height_mm * 1e-3;
      script.entry_W_m = Eigen::Vector3d(entry_x_mm * 1e-3, entry_y_mm * 1e-3, 0.0);
      script.seed = static_cast<std::uint32_t>(seed);
      device = std::make_unique<hapsim::bridge::SyntheticDevice>(script);
    } else if (backend == "replay") {
      if (replay_file.empty()) throw std::invalid_argument("--backend replay needs --replay-file");
      device = std::make_unique<hapsim::bridge::ReplayDevice>(hapsim::bridge::LoadPoseLog(replay_file));
    } else {
      throw std::invalid_argument("unknown backend '" + backend + "' (synthetic or replay)");
    }

    hapsim::bridge::BridgeDds dds({static_cast<std::uint32_t>(dds_domain), dds_config},
                                  static_cast<std::uint32_t>(device_id), session);
    spdlog::info("DDS domain {} with config: {}", dds_domain, dds.config_origin());
    dds.Start();

    hapsim::bridge::ServoConfig servo_config;
    servo_config.device_id = static_cast<std::uint32_t>(device_id);
    servo_config.session = session;
    servo_config.rate_hz = rate_hz;
    servo_config.run_seconds = seconds;
    servo_config.safety = safety;
    servo_config.stop_when_script_finishes = !keep_running;
    servo_config.trace_capacity = trace_file.empty() ? 0 : static_cast<std::size_t>(rate_hz * 600.0);
    hapsim::bridge::ServoLoop servo(device.get(), servo_config, &dds.pose_outbox(), &dds.model_inbox(),
                                    [&dds] { dds.Wake(); });

    std::atomic<bool> stop{false};
    asio::io_context io;
    asio::signal_set signals(io, SIGINT, SIGTERM);
    signals.async_wait([&](const std::error_code& ec, int signal) {
      if (!ec) spdlog::info("signal {} received: stopping", signal);
      stop = true;
    });
    std::thread signal_thread([&io] { io.run(); });

    spdlog::info("servo loop at {} Hz on device {} for session '{}'", rate_hz, device->Name(), session);
    const auto report = servo.Run(stop);
    device->CommandForce(Eigen::Vector3d::Zero());  // leave the motors off
    io.stop();
    signal_thread.join();
    dds.Stop();
    if (!trace_file.empty() && !hapsim::bridge::WriteTraceCsv(trace_file, report.trace)) {
      spdlog::error("cannot write trace to {}", trace_file);
    }
    const char* final_state = report.ticks ? hapsim::bridge::ToString(
                                                 report.trace.empty() ? hapsim::bridge::WatchdogState::kFresh
                                                                      : report.trace.back().watchdog)
                                           : "no-model";
    PrintReport(report, device->Name(), session, dds, final_state);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "hapsim-bridge: %s\n", e.what());
    return 1;
  }
  return 0;
}
