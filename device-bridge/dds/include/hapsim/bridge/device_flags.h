// Command-line flags that hapsim-bridge and hapsim-load share: the synthetic
// script of a device and its force-safety chain, in the units a person types
// (mm, ms), converted to the SI structs in one place; DDS and logging; and
// the parse-then-set-up-logging step of main().
#pragma once
#include <string>

#include "backends/synthetic_device.h"
#include "hapsim/common/flags.h"
#include "hapsim/dds/dds.h"
#include "hapsim/servo/force_safety.h"
#include "hapsim/servo/pose_deadband.h"

namespace hapsim::bridge {

struct ScriptFlags {
  std::string kind = "insertion";
  double depth_mm = 5.0, speed_mm_s = 10.0, start_height_mm = 10.0, hold_s = 0.5;
  double entry_x_mm = 0.0, entry_y_mm = 0.0;
  double cut_length_mm = 20.0, cut_angle_deg = 0.0, cut_bend_deg = 0.0, blade_tilt_deg = 30.0;
  int seed = 1;
  SyntheticScript ToScript() const;
};
void AddScriptFlags(common::Flags& flags, ScriptFlags* script, const std::string& seed_help);

struct SafetyFlags {
  double max_force_N = SafetyConfig{}.max_force_N, max_rise_N_per_s = SafetyConfig{}.max_rise_N_per_s;
  double warn_ms = 20.0, fade_ms = 50.0, disarm_ms = 100.0;                       // stream gap
  double delay_warn_ms = 50.0, delay_fade_ms = 1000.0, delay_disarm_ms = 2000.0;  // physics age
  double max_stiffness_N_per_m = SafetyConfig{}.max_stiffness_N_per_m;
  double max_damping_Ns_per_m = SafetyConfig{}.max_damping_Ns_per_m;
  double max_velocity_m_per_s = SafetyConfig{}.max_velocity_m_per_s;
  double max_continuous_force_N = SafetyConfig{}.max_continuous_force_N;
  double ramp_in_s = SafetyConfig{}.ramp_in_s;
  int arm_button = 0;  // 0: none (always armed); 1-4: HD_DEVICE_BUTTON_1..4
  bool no_passivity = !SafetyConfig{}.passivity_control;
  SafetyConfig ToConfig() const;  // throws std::invalid_argument when the limits are not ordered/positive
};
void AddSafetyFlags(common::Flags& flags, SafetyFlags* safety);

// Which poses go out (PoseDeadband): every one unless --pose-deadband-mm.
struct PoseDeadbandFlags {
  double position_mm = 0.05, velocity_mm_s = 5.0, keepalive_ms = 25.0;
  PoseDeadbandConfig ToConfig() const;  // throws std::invalid_argument naming a flag out of range
};
void AddPoseDeadbandFlags(common::Flags& flags, PoseDeadbandFlags* deadband);

struct ProcessFlags {
  int dds_domain = 0;
  int rt_priority = 0;     // SCHED_FIFO priority of the servo thread(s); the DDS receive threads one above; 0: off
  std::string dds_config;  // empty: CYCLONEDDS_URI if set, else the built-in loopback config
  std::string log_level = "info";
  dds::Options Dds() const { return {static_cast<std::uint32_t>(dds_domain), dds_config}; }
};
void AddProcessFlags(common::Flags& flags, ProcessFlags* process);

// --rt-priority on the servo thread calling it (after the DDS side started):
// this thread at SCHED_FIFO `priority`, the DDS receive threads one above, so
// a 1 kHz servo tick and the force models it waits for are never held up by
// other programs on the core. Logs what was done or refused (never fatal).
// No-op at 0.
void RaiseServoPath(int priority);

// Parses argv into flags, checks the DDS domain and sets up logging under
// log_name. Returns -1 to go on; otherwise main() returns the value: 0 after
// printing --help, 2 after printing what was wrong as "<program>: ...".
int ParseCommandLine(common::Flags& flags, int argc, char** argv, const ProcessFlags& process, const char* program,
                     const char* log_name);

}  // namespace hapsim::bridge
