#include "hapsim/bridge/device_flags.h"

#include <spdlog/spdlog.h>

#include <cstdio>
#include <stdexcept>

#include "hapsim/common/logging.h"
#include "hapsim/common/thread_setup.h"
#include "hapsim/dds/io_thread.h"

namespace hapsim::bridge {

SyntheticScript ScriptFlags::ToScript() const {
  SyntheticScript s;
  s.kind = kind;
  s.depth_m = depth_mm * 1e-3;
  s.speed_m_per_s = speed_mm_s * 1e-3;
  s.start_height_m = start_height_mm * 1e-3;
  s.hold_s = hold_s;
  s.entry_W_m = Eigen::Vector3d(entry_x_mm * 1e-3, entry_y_mm * 1e-3, 0.0);
  s.seed = static_cast<std::uint32_t>(seed);
  constexpr double kRad = 3.14159265358979323846 / 180.0;
  s.cut_length_m = cut_length_mm * 1e-3;
  s.cut_angle_rad = cut_angle_deg * kRad;
  s.cut_bend_rad = cut_bend_deg * kRad;
  s.blade_tilt_rad = blade_tilt_deg * kRad;
  return s;
}

void AddScriptFlags(common::Flags& flags, ScriptFlags* s, const std::string& seed_help) {
  flags.Add("script", &s->kind, "synthetic script: insertion, constant_speed, random_walk, hold or cut");
  flags.Add("depth-mm", &s->depth_mm, "synthetic: deepest tip position below the surface [mm]");
  flags.Add("speed-mm-s", &s->speed_mm_s, "synthetic: tip speed [mm/s]");
  flags.Add("start-height-mm", &s->start_height_mm, "synthetic: height above the surface where motion starts [mm]");
  flags.Add("hold-s", &s->hold_s, "synthetic insertion: time held at depth [s]");
  flags.Add("entry-x-mm", &s->entry_x_mm, "synthetic: x of the entry point on the surface [mm]");
  flags.Add("entry-y-mm", &s->entry_y_mm, "synthetic: y of the entry point on the surface [mm]");
  flags.Add("cut-length-mm", &s->cut_length_mm, "synthetic cut: incision length [mm]");
  flags.Add("cut-angle-deg", &s->cut_angle_deg, "synthetic cut: heading of the stroke in the skin plane (0: +x) [deg]");
  flags.Add("cut-bend-deg", &s->cut_bend_deg, "synthetic cut: heading change over the stroke (0: straight) [deg]");
  flags.Add("blade-tilt-deg", &s->blade_tilt_deg, "synthetic cut: blade leaning back from vertical [deg]");
  flags.Add("seed", &s->seed, seed_help);
}

SafetyConfig SafetyFlags::ToConfig() const {
  SafetyConfig c;
  c.max_force_N = max_force_N;
  c.max_rise_N_per_s = max_rise_N_per_s;
  c.warn_age_s = warn_ms * 1e-3;
  c.fade_start_age_s = fade_ms * 1e-3;
  c.disarm_age_s = disarm_ms * 1e-3;
  c.delay_warn_age_s = delay_warn_ms * 1e-3;
  c.delay_fade_start_age_s = delay_fade_ms * 1e-3;
  c.delay_disarm_age_s = delay_disarm_ms * 1e-3;
  c.max_stiffness_N_per_m = max_stiffness_N_per_m;
  c.max_damping_Ns_per_m = max_damping_Ns_per_m;
  c.max_velocity_m_per_s = max_velocity_m_per_s;
  c.max_continuous_force_N = max_continuous_force_N;
  c.ramp_in_s = ramp_in_s;
  if (arm_button < 0 || arm_button > 4) throw std::invalid_argument("--arm-button must be 0 (none) or 1-4");
  c.arm_button_mask = arm_button == 0 ? 0u : 1u << (arm_button - 1);
  c.passivity_control = !no_passivity;
  ValidateSafetyConfig(c);
  return c;
}

PoseDeadbandConfig PoseDeadbandFlags::ToConfig() const {
  const std::string out_of_range = common::FirstFlagOutOfRange({
      {position_mm >= 0.0 && position_mm <= 10.0, "--pose-deadband-mm", "[0, 10]"},
      {velocity_mm_s > 0.0 && velocity_mm_s <= 1000.0, "--pose-deadband-velocity-mm-s", "(0, 1000]"},
      {keepalive_ms > 0.0 && keepalive_ms <= 200.0, "--pose-keepalive-ms", "(0, 200]"},
  });
  if (!out_of_range.empty()) throw std::invalid_argument(out_of_range);
  PoseDeadbandConfig c;
  c.position_m = position_mm * 1e-3;
  c.velocity_m_per_s = velocity_mm_s * 1e-3;
  c.keepalive_s = keepalive_ms * 1e-3;
  return c;
}

void AddPoseDeadbandFlags(common::Flags& flags, PoseDeadbandFlags* d) {
  flags.Add(
      "pose-deadband-mm", &d->position_mm,
      "send a pose only when it is this far from where the server extrapolates the last one sent\n"
      "(or its velocity changed, its buttons changed, or a keep-alive is due; docs/deploy.md). 0: every tick [mm]");
  flags.Add("pose-deadband-velocity-mm-s", &d->velocity_mm_s,
            "with --pose-deadband-mm: a velocity change that sends a pose [mm/s]");
  flags.Add("pose-keepalive-ms", &d->keepalive_ms, "with --pose-deadband-mm: a pose goes out at least this often [ms]");
}

void AddSafetyFlags(common::Flags& flags, SafetyFlags* s) {
  flags.Add("max-force-n", &s->max_force_N, "force clamp [N] (Phantom Omni peak: 3.3 N)");
  flags.Add("max-force-rise-n-per-s", &s->max_rise_N_per_s, "largest rise of the force magnitude [N/s]");
  flags.Add("watchdog-warn-ms", &s->warn_ms, "no new model for this long: warning [ms]");
  flags.Add("watchdog-fade-ms", &s->fade_ms, "no new model for this long: force fades out [ms]");
  flags.Add("watchdog-disarm-ms", &s->disarm_ms, "no new model for this long: zero force until a fresh model [ms]");
  flags.Add("watchdog-delay-warn-ms", &s->delay_warn_ms,
            "model's physics older than this (round trip + gap): felt-lag warning [ms]");
  flags.Add("watchdog-delay-fade-ms", &s->delay_fade_ms, "model's physics older than this: force fades out [ms]");
  flags.Add("watchdog-delay-disarm-ms", &s->delay_disarm_ms,
            "model's physics older than this: zero force until a model with recent physics [ms]");
  flags.Add("max-stiffness-n-per-m", &s->max_stiffness_N_per_m,
            "stiffest spring rendered [N/m] (lower if the device says so; Omni 700, Touch 400)");
  flags.Add("max-damping-ns-per-m", &s->max_damping_Ns_per_m, "largest damping rendered [N s/m]");
  flags.Add("max-velocity-m-s", &s->max_velocity_m_per_s, "above this stylus speed the force is zero [m/s]");
  flags.Add("max-continuous-force-n", &s->max_continuous_force_N,
            "average force the motors may hold, when the device does not say [N]");
  flags.Add("ramp-in-s", &s->ramp_in_s, "force ramp after each arming [s] (0: none)");
  flags.Add("arm-button", &s->arm_button, "stylus button (1-4) that toggles force output (0: always armed)");
  flags.Add("no-passivity", &s->no_passivity, "turn off the time-domain passivity controller (tests only)");
}

void AddProcessFlags(common::Flags& flags, ProcessFlags* p) {
  flags.Add("dds-domain", &p->dds_domain, "DDS domain id (0..232)");
  flags.Add("dds-config", &p->dds_config, "Cyclone DDS config file (default: CYCLONEDDS_URI if set, else built-in loopback)");
  flags.Add("log-level", &p->log_level, "trace, debug, info, warn, error or off");
  flags.Add("rt-priority", &p->rt_priority,
            "run the servo thread at this SCHED_FIFO priority and the DDS threads one above (needs\n"
            "CAP_SYS_NICE or LimitRTPRIO; refused: a warning, normal priority). 0: normal scheduling");
}

void RaiseServoPath(int priority) {
  if (priority <= 0) return;
  const bool servo = common::RunThisThreadAtRealtime(priority);
  const auto dds_threads = dds::RaiseDdsThreads(priority + 1);
  if (!servo || dds_threads.refused > 0) {
    spdlog::warn(
        "real-time priority refused (needs CAP_SYS_NICE or LimitRTPRIO >= {}): the servo loop runs at "
        "normal priority",
        priority + 1);
    return;
  }
  spdlog::info("real-time priority: servo thread at SCHED_FIFO {}, {} DDS threads at {}", priority, dds_threads.raised,
               priority + 1);
}

int ParseCommandLine(common::Flags& flags, int argc, char** argv, const ProcessFlags& process, const char* program,
                     const char* log_name) {
  std::string error;
  switch (flags.Parse(argc, argv, &error)) {
    case common::Flags::Result::kHelp: std::fputs(flags.Help().c_str(), stdout); return 0;
    case common::Flags::Result::kVersion:
      std::fputs(flags.Version().c_str(), stdout);
      return 0;
    case common::Flags::Result::kError: std::fprintf(stderr, "%s: %s\n", program, error.c_str()); return 2;
    case common::Flags::Result::kOk: break;
  }
  if (process.dds_domain < 0 || process.dds_domain > 232) {
    std::fprintf(stderr, "%s: --dds-domain must be in 0..232\n", program);
    return 2;
  }
  if (process.rt_priority < 0 || process.rt_priority > 98) {
    std::fprintf(stderr, "%s: --rt-priority must be within [0, 98]\n", program);
    return 2;
  }
  if (!common::SetUpLogging(log_name, process.log_level)) {
    std::fprintf(stderr, "%s: unknown --log-level '%s'\n", program, process.log_level.c_str());
    return 2;
  }
  return -1;
}

}  // namespace hapsim::bridge
