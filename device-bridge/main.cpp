// hapsim-bridge: the device-bridge process. Reads a haptic device at 1 kHz
// (synthetic, replay, or a Phantom Omni / Touch through the OpenHaptics
// runtime loaded at run time), streams its pose over DDS, and renders the
// server's local force model through the safety chain. Prints a summary at
// exit.
#include <spdlog/spdlog.h>

#include <atomic>
#include <cmath>
#include <cstdio>
#include <memory>
#include <thread>
#include <vector>

#include "backends/openhaptics_device.h"
#include "backends/replay_device.h"
#include "backends/synthetic_device.h"
#include "hapsim/bridge/bridge_dds.h"
#include "hapsim/bridge/device_flags.h"
#include "hapsim/common/flags.h"
#include "hapsim/common/session_id.h"
#include "hapsim/common/shutdown_deadline.h"
#include "hapsim/common/thread_setup.h"
#include "hapsim/servo/servo_loop.h"
#include "session_join.h"
#include "stop_on_signal.h"

namespace {

// The safety chain's counters of one device.
void PrintSafety(const hapsim::bridge::SafetyCounters& s, hapsim::bridge::WatchdogState watchdog) {
  using ull = unsigned long long;
  std::printf(
      "bridge: safety clamped %llu, rise-limited %llu, non-finite %llu, disarms %llu, watchdog %s "
      "(warnings %llu, fades %llu, delay warnings %llu)\n",
      static_cast<ull>(s.clamped), static_cast<ull>(s.rate_limited), static_cast<ull>(s.non_finite),
      static_cast<ull>(s.disarms), hapsim::bridge::ToString(watchdog), static_cast<ull>(s.warnings),
      static_cast<ull>(s.fades), static_cast<ull>(s.delay_warnings));
  std::printf(
      "bridge: device safety: models capped %llu, model jumps %llu (steps limited %llu), velocity-limited "
      "%llu, passivity corrected %llu (bounded %llu, uncorrected %llu), ramp-in %llu, derated %llu, arm toggles %llu\n",
      static_cast<ull>(s.models_capped), static_cast<ull>(s.model_jumps), static_cast<ull>(s.jump_steps_limited),
      static_cast<ull>(s.velocity_limited), static_cast<ull>(s.passivity_corrected),
      static_cast<ull>(s.passivity_bounded), static_cast<ull>(s.passivity_uncorrected),
      static_cast<ull>(s.ramp_limited), static_cast<ull>(s.derated), static_cast<ull>(s.arm_toggles));
}

void PrintReport(const hapsim::bridge::ServoReport& r, const std::string& device, const std::string& session,
                 const hapsim::bridge::BridgeDds& dds, std::size_t i) {
  using hapsim::common::FormatPercentiles;
  using ull = unsigned long long;
  const hapsim::bridge::ChannelCounters& c = r.channel;
  std::printf("bridge: device %s, session %s\n", device.c_str(), session.c_str());
  std::printf("bridge: loop %.1f Hz over %.2f s (%llu ticks)\n",
              r.elapsed_s > 0 ? static_cast<double>(c.ticks) / r.elapsed_s : 0.0, r.elapsed_s,
              static_cast<ull>(c.ticks));
  std::printf("bridge: period jitter %s\n", FormatPercentiles(r.period_error_s, 1e3, "ms").c_str());
  std::printf(
      "bridge: poses sent %llu (deadband let out %llu of %llu); force models received %llu (echoed pose seq %llu -> "
      "%llu, regressions %llu, unused %llu)\n",
      static_cast<ull>(dds.poses_written(i)), static_cast<ull>(c.poses_due), static_cast<ull>(c.ticks),
      static_cast<ull>(c.models_taken), static_cast<ull>(c.first_echo_seq), static_cast<ull>(c.last_echo_seq),
      static_cast<ull>(c.echo_regressions), static_cast<ull>(c.models_unused));
  std::printf("bridge: DDS partition %s; models for other sessions or devices %llu (expected 0)\n",
              hapsim::dds::SessionPartition(session).c_str(), static_cast<ull>(dds.models_for_others()));
  std::printf(
      "bridge: following server %016llx; models from another server dropped %llu (expected 0), "
      "server switches %llu\n",
      static_cast<ull>(dds.followed_server(i)), static_cast<ull>(dds.models_from_other_servers(i)),
      static_cast<ull>(dds.server_switches(i)));
  if (r.first_model_s >= 0.0) {
    std::printf(
        "bridge: first force model %.3f s after the servo started (zero force before: discovering the server)\n",
        r.first_model_s);
  } else {
    std::printf("bridge: no force model arrived (zero force throughout)\n");
  }
  std::printf("bridge: round trip %s\n", FormatPercentiles(r.round_trip_s, 1e3, "ms").c_str());
  std::printf("bridge: model age %s\n", FormatPercentiles(r.model_age_s, 1e3, "ms").c_str());
  std::printf("bridge: physics age %s\n", FormatPercentiles(r.physics_age_s, 1e3, "ms").c_str());
  std::printf("bridge: force peak %.3f N (pressing %.3f N, withdrawn %.3f N)\n", c.peak_force_N,
              c.peak_force_pressing_N, c.peak_force_withdrawn_N);
  PrintSafety(r.safety, r.final_watchdog);
  std::fflush(stdout);
}

// The OpenHaptics backend's flags.
struct OpenHapticsFlags {
  std::string library = "libHD.so", device_name, offset_mm = "0,0,0";
  double workspace_scale = 1.0, calibration_wait_s = 30.0, stall_ms = 10.0;

  void Add(hapsim::common::Flags& flags) {
    flags.Add("hd-library", &library, "openhaptics: the HD runtime to load (a library name or path)");
    flags.Add("hd-device", &device_name, "openhaptics: the HD device configuration name (empty: the default)");
    flags.Add("workspace-scale", &workspace_scale, "openhaptics: world metres per device metre");
    flags.Add("workspace-offset-mm", &offset_mm, "openhaptics: X,Y,Z of the device origin in the world [mm]");
    flags.Add("hd-calibration-wait-s", &calibration_wait_s,
              "openhaptics: how long to wait for the stylus in its inkwell when it needs calibrating [s]");
    flags.Add("hd-stall-ms", &stall_ms, "openhaptics: a servo scheduler gap counted as a stall [ms]");
  }
  // Throws std::invalid_argument naming the bad flag.
  hapsim::bridge::OpenHapticsConfig ToConfig() const {
    hapsim::bridge::OpenHapticsConfig c;
    c.library = library;
    c.device_name = device_name;
    c.workspace.scale = workspace_scale;
    double x = 0, y = 0, z = 0;
    char rest = 0;
    if (std::sscanf(offset_mm.c_str(), "%lf,%lf,%lf%c", &x, &y, &z, &rest) != 3) {
      throw std::invalid_argument("--workspace-offset-mm must be X,Y,Z in millimetres");
    }
    c.workspace.offset_W_m = Eigen::Vector3d(x, y, z) * 1e-3;
    c.calibration_wait_s = calibration_wait_s;
    c.stall_timeout_s = stall_ms * 1e-3;
    hapsim::bridge::ValidateOpenHapticsConfig(c);
    return c;
  }
};

// The flags of hapsim-bridge.
struct BridgeFlags {
  std::string session = "demo", backend = "synthetic", replay_file, trace_file;
  std::vector<std::string> devices;  // --device SESSION[:HD_DEVICE], repeated
  OpenHapticsFlags openhaptics;
  int device_id = 1;
  double seconds = 0.0, rate_hz = 1000.0, model_delay_ms = 0.0;
  hapsim::bridge::PoseDeadbandFlags pose_deadband;
  hapsim::bridge::ScriptFlags script;
  hapsim::bridge::SafetyFlags safety;
  hapsim::bridge::ProcessFlags process;
  hapsim::bridge::SessionJoiner joiner;  // --join
  bool keep_running = false;
};

// In the order --help lists them.
void AddBridgeFlags(hapsim::common::Flags& flags, BridgeFlags* f) {
  flags.Add("session", &f->session, "session id to drive");
  flags.Add("device-id", &f->device_id,
            "device id (unique per device on the DDS domain; the next ones for more devices)");
  flags.AddList("device", &f->devices,
                "a device and the session it drives, SESSION[:HD_DEVICE] (repeat for several devices: one servo "
                "thread each, one DDS participant; replaces --session)");
  flags.Add("backend", &f->backend, "synthetic, replay or openhaptics");
  hapsim::bridge::AddScriptFlags(flags, &f->script, "synthetic random_walk: seed");
  flags.Add("replay-file", &f->replay_file, "replay: pose log CSV (t_s,x_m,y_m,z_m,qw,qx,qy,qz,...)");
  f->openhaptics.Add(flags);
  flags.Add("seconds", &f->seconds, "stop after this long [s] (0: until SIGINT/SIGTERM)");
  flags.Add("keep-running", &f->keep_running, "keep running after a finite script or replay ends");
  flags.Add("rate-hz", &f->rate_hz, "servo loop rate [Hz]");
  flags.Add("model-delay-ms", &f->model_delay_ms,
            "measurement: hold every force model this long before the servo sees it, as a longer link would [ms]");
  hapsim::bridge::AddPoseDeadbandFlags(flags, &f->pose_deadband);
  hapsim::bridge::AddSafetyFlags(flags, &f->safety);
  f->joiner.AddFlags(&flags);
  flags.Add("trace", &f->trace_file, "write a per-tick CSV trace here (first 10 minutes; replayable)");
  hapsim::bridge::AddProcessFlags(flags, &f->process);
}

// One device the bridge drives: its session and, for openhaptics, the HD
// device configuration name (empty: --hd-device).
struct DeviceSpec {
  std::string session, hd_device;
};

// --device SESSION[:HD_DEVICE]..., or the one --session. Throws
// std::invalid_argument naming a bad or repeated session.
std::vector<DeviceSpec> DeviceSpecs(const BridgeFlags& f) {
  std::vector<DeviceSpec> specs;
  for (const std::string& d : f.devices) {
    const std::size_t colon = d.find(':');
    DeviceSpec spec{d.substr(0, colon), colon == std::string::npos ? "" : d.substr(colon + 1)};
    if (!hapsim::common::IsValidSessionId(spec.session)) {
      throw std::invalid_argument("--device '" + d.substr(0, 80) + "': the session must be [A-Za-z0-9_-]{1,63}");
    }
    for (const DeviceSpec& other : specs) {
      if (other.session == spec.session) throw std::invalid_argument("--device: session '" + spec.session + "' twice");
    }
    specs.push_back(spec);
  }
  if (specs.size() > 16) throw std::invalid_argument("--device: at most 16 devices per bridge");
  if (specs.empty()) specs.push_back({f.session, ""});
  return specs;
}

// False (after saying which) if a flag is out of its range.
bool BridgeFlagsInRange(const BridgeFlags& f) {
  const std::string out_of_range = hapsim::common::FirstFlagOutOfRange({
      {f.rate_hz >= 100.0 && f.rate_hz <= 10000.0, "--rate-hz", "[100, 10000]"},
      {f.seconds >= 0.0 && f.seconds <= hapsim::common::kMaxFlagSeconds, "--seconds",
       hapsim::common::kMaxFlagSecondsRange},
      {f.device_id >= 0, "--device-id", ">= 0"},
      {f.model_delay_ms >= 0.0 && f.model_delay_ms <= 1000.0, "--model-delay-ms", "[0, 1000]"},
      {hapsim::common::IsValidSessionId(f.session), "--session", "[A-Za-z0-9_-]{1,63}"},
  });
  if (!out_of_range.empty()) {
    std::fprintf(stderr, "hapsim-bridge: %s\n", out_of_range.c_str());
    return false;
  }
  return true;
}

// Flags that are wrong together or out of range in the script or safety
// settings: false (after saying which), so main exits 2 like any bad flag (a
// replay file that cannot be read is a runtime error, exit 1, in RunBridge).
// Devices are opened in RunBridge (a replay file or a device that cannot
// start is a runtime error); their flags are checked here.
bool ConfigureBridge(const BridgeFlags& f, hapsim::bridge::SafetyConfig* safety_config,
                     std::vector<DeviceSpec>* specs) {
  try {
    *safety_config = f.safety.ToConfig();
    (void)f.pose_deadband.ToConfig();  // throws on a flag out of range
    *specs = DeviceSpecs(f);
    if (f.backend == "synthetic") {
      (void)hapsim::bridge::SyntheticDevice(f.script.ToScript());  // throws on a bad script
    } else if (f.backend == "replay") {
      if (f.replay_file.empty()) throw std::invalid_argument("--backend replay needs --replay-file");
    } else if (f.backend == "openhaptics") {
      (void)f.openhaptics.ToConfig();  // bad flags before anything opens
    } else {
      throw std::invalid_argument("unknown backend '" + f.backend + "' (synthetic, replay or openhaptics)");
    }
  } catch (const std::invalid_argument& e) {
    std::fprintf(stderr, "hapsim-bridge: %s\n", e.what());
    return false;
  }
  return true;
}

// Device i of the bridge: its own backend instance.
std::unique_ptr<hapsim::bridge::HapticDevice> OpenDevice(const BridgeFlags& f, const DeviceSpec& spec) {
  if (f.backend == "synthetic") return std::make_unique<hapsim::bridge::SyntheticDevice>(f.script.ToScript());
  if (f.backend == "openhaptics") {
    hapsim::bridge::OpenHapticsConfig config = f.openhaptics.ToConfig();
    if (!spec.hd_device.empty()) config.device_name = spec.hd_device;
    return std::make_unique<hapsim::bridge::OpenHapticsDevice>(config);
  }
  return std::make_unique<hapsim::bridge::ReplayDevice>(hapsim::bridge::LoadPoseLog(f.replay_file));
}

hapsim::bridge::ServoConfig MakeBridgeServoConfig(const BridgeFlags& f,
                                                  const hapsim::bridge::SafetyConfig& safety_config, std::size_t i,
                                                  const std::string& session) {
  hapsim::bridge::ServoConfig servo_config;
  servo_config.device_id = static_cast<std::uint32_t>(f.device_id) + static_cast<std::uint32_t>(i);
  servo_config.session = session;
  servo_config.rate_hz = f.rate_hz;
  servo_config.run_seconds = f.seconds;
  servo_config.safety = safety_config;
  servo_config.model_delay_s = f.model_delay_ms * 1e-3;
  servo_config.pose_deadband = f.pose_deadband.ToConfig();
  servo_config.stop_when_script_finishes = !f.keep_running;
  // The trace is the first device's.
  servo_config.trace_capacity = f.trace_file.empty() || i > 0 ? 0 : static_cast<std::size_t>(f.rate_hz * 600.0);
  return servo_config;
}

// Device i's summary (and, for a real device, its scheduler's); false if
// the device faulted.
bool ReportDevice(const hapsim::bridge::ServoReport& report, const hapsim::bridge::HapticDevice& device,
                  const std::string& session, const hapsim::bridge::BridgeDds& dds, std::size_t i) {
  PrintReport(report, device.Name(), session, dds, i);
  const auto* hd = dynamic_cast<const hapsim::bridge::OpenHapticsDevice*>(&device);
  if (!hd) return true;
  const hapsim::bridge::OpenHapticsCounters c = hd->counters();
  std::printf(
      "bridge: device scheduler %llu ticks, stalls %llu, longest gap %.1f ms, motor temperature %s (ticks derated "
      "for heat %llu)\n",
      static_cast<unsigned long long>(c.ticks), static_cast<unsigned long long>(c.stalls), c.longest_gap_s * 1e3,
      c.max_motor_temperature < 0 ? "not reported" : std::to_string(c.max_motor_temperature).c_str(),
      static_cast<unsigned long long>(c.thermal_derated_ticks));
  std::fflush(stdout);
  if (hd->fault().empty()) return true;
  std::fprintf(stderr, "hapsim-bridge: device fault on '%s', force output stopped at zero: %s\n", session.c_str(),
               hd->fault().c_str());
  return false;
}

// One servo loop per device, the first on this thread, the others on their
// own, until all have ended; their reports, in device order.
std::vector<hapsim::bridge::ServoReport> RunServoLoops(
    const BridgeFlags& f, const hapsim::bridge::SafetyConfig& safety_config,
    const std::vector<std::unique_ptr<hapsim::bridge::HapticDevice>>& devices, const std::vector<std::string>& sessions,
    hapsim::bridge::BridgeDds& dds) {
  std::vector<hapsim::bridge::ServoLoop> loops;
  for (std::size_t i = 0; i < devices.size(); ++i) {
    loops.emplace_back(devices[i].get(), MakeBridgeServoConfig(f, safety_config, i, sessions[i]), &dds.pose_outbox(i),
                       &dds.model_inbox(i), [&dds] { dds.Wake(); });
    spdlog::info("servo loop at {} Hz on device {} (id {}) for session '{}'", f.rate_hz, devices[i]->Name(),
                 f.device_id + static_cast<int>(i), sessions[i]);
  }
  std::atomic<bool> stop{false};
  std::vector<hapsim::bridge::ServoReport> reports(devices.size());
  {
    hapsim::bridge::StopOnSignal stop_on_signal(&stop);
    std::vector<std::thread> others;
    for (std::size_t i = 1; i < loops.size(); ++i) {
      others.emplace_back([&, i] {
        if (f.process.rt_priority > 0) (void)hapsim::common::RunThisThreadAtRealtime(f.process.rt_priority);
        reports[i] = loops[i].Run(stop);
      });
    }
    hapsim::bridge::RaiseServoPath(f.process.rt_priority);  // this thread runs loop 0
    reports[0] = loops[0].Run(stop);
    for (std::thread& t : others) t.join();
    for (auto& device : devices) device->CommandForce(Eigen::Vector3d::Zero());  // leave the motors off
  }
  return reports;
}

// Teardown (the trace, the report, DDS) normally takes well under a second.
constexpr double kTeardownLimitS = 3.0;

// Every device's servo loop (one thread each; the first on this one) until
// the scripts end, --seconds pass or a signal comes; the process's exit code.
int RunBridge(BridgeFlags& f, const hapsim::bridge::SafetyConfig& safety_config, const std::vector<DeviceSpec>& specs) {
  // Outlives the DDS participant, whose deletion can block for good when the
  // network interface has vanished (shutdown_deadline.h).
  hapsim::common::ShutdownDeadline deadline("hapsim-bridge");
  try {
    std::vector<std::unique_ptr<hapsim::bridge::HapticDevice>> devices;
    std::vector<std::string> sessions;
    for (const DeviceSpec& spec : specs) {
      devices.push_back(OpenDevice(f, spec));
      sessions.push_back(spec.session);
    }
    if (f.joiner.enabled()) f.process.dds_domain = static_cast<int>(f.joiner.JoinAll(sessions));
    hapsim::bridge::BridgeDds dds(f.process.Dds(), static_cast<std::uint32_t>(f.device_id), sessions);
    spdlog::info("DDS domain {} with config: {}", f.process.dds_domain, dds.config_origin());
    dds.Start();

    std::vector<hapsim::bridge::ServoReport> reports = RunServoLoops(f, safety_config, devices, sessions, dds);
    deadline.Arm(kTeardownLimitS);  // the motors are at zero: nothing after this may hold the process
    for (std::size_t i = 0; i < sessions.size(); ++i) {
      if (dds.matched_servers(i) == 0) {
        spdlog::warn("no server serves session '{}' (nothing matched its DDS partition {}): is the session created?",
                     sessions[i], hapsim::dds::SessionPartition(sessions[i]));
      }
    }
    dds.Stop();
    if (!f.trace_file.empty() && !hapsim::bridge::WriteTraceCsv(f.trace_file, reports[0].trace)) {
      spdlog::error("cannot write trace to {}", f.trace_file);
    }
    bool healthy = true;
    for (std::size_t i = 0; i < devices.size(); ++i)
      healthy &= ReportDevice(reports[i], *devices[i], sessions[i], dds, i);
    deadline.set_exit_code(healthy ? 0 : 1);
    return deadline.exit_code();
  } catch (const std::exception& e) {
    std::fprintf(stderr, "hapsim-bridge: %s\n", e.what());
    return 1;
  }
}

}  // namespace

int main(int argc, char** argv) {
  BridgeFlags f;
  hapsim::common::Flags flags(
      "hapsim-bridge",
      "Device-bridge of hapsim: reads a haptic device at the servo rate, publishes its pose over DDS,\n"
      "and renders the physics server's local force model with a force clamp, a rise-rate limit and a\n"
      "staleness watchdog. Backends: synthetic (scripted motion), replay (pose log CSV), openhaptics\n"
      "(a Phantom Omni / Touch through the vendor's HD runtime, loaded at run time: docs/device.md).\n\n"
      "Exit: 0 done, 1 runtime error (DDS, an unreadable replay file, a device that cannot start or\n"
      "faulted), 2 bad flags.");
  AddBridgeFlags(flags, &f);
  const int parse_exit = hapsim::bridge::ParseCommandLine(flags, argc, argv, f.process, "hapsim-bridge", "bridge");
  if (parse_exit >= 0) return parse_exit;
  if (!BridgeFlagsInRange(f)) return 2;
  hapsim::bridge::SafetyConfig safety_config;
  std::vector<DeviceSpec> specs;
  if (!ConfigureBridge(f, &safety_config, &specs)) return 2;
  return RunBridge(f, safety_config, specs);
}
