// Which synthetic devices hapsim-load runs: device i has id
// first_device_id + i, drives session `<prefix><i>` (or sessions[i] when a
// list is given), runs the common script with seed base + i, and reads it
// at a phase offset i * phase_spread_s / N, so the devices press and
// withdraw at staggered times instead of in lockstep. Each device also
// ticks on a clock of its own (DeviceClocks): its phase i / N of
// clock_phase_spread periods after device 0's, its rate off by an amount
// spread evenly over +-clock_rate_ppm — as a classroom's devices, whose
// poses reach the server spread over the period, not all at once.
#pragma once
#include <cstdint>
#include <string>
#include <vector>

#include "backends/synthetic_device.h"

namespace hapsim::bridge {

struct LoadPlanOptions {
  int devices = 16;
  std::string session_prefix = "load-";
  std::vector<std::string> sessions;  // non-empty: these sessions, one device each (overrides devices/prefix)
  std::uint32_t first_device_id = 1000;
  SyntheticScript script;             // script.seed is the base seed
  double phase_spread_s = 1.0;
  double clock_phase_spread = 1.0;  // [periods], [0, 1]: 0 with clock_rate_ppm 0 steps every device together
  double clock_rate_ppm = 500.0;    // [ppm], [0, 10000]
  double period_s = 1e-3;           // the nominal servo period the phases are fractions of
};

struct LoadDevicePlan {
  std::uint32_t device_id = 0;
  std::string session;
  SyntheticScript script;
  double phase_s = 0.0;  // the device reads its script at t + phase_s
  double clock_phase_s = 0.0;   // its servo clock's first tick, in [0, period)
  double clock_rate_ppm = 0.0;  // its servo clock's rate error
};

// True when any device of the plan has a clock of its own (else all tick together).
bool HasOwnClocks(const std::vector<LoadDevicePlan>& plan);

// Throws std::invalid_argument for a bad count, a malformed or repeated
// session id ([A-Za-z0-9_-]{1,63}), a negative spread or a clock option
// out of its range.
std::vector<LoadDevicePlan> PlanDevices(const LoadPlanOptions& options);

// "a,b,,c" -> {"a", "b", "c"}
std::vector<std::string> SplitCommaList(const std::string& text);

}  // namespace hapsim::bridge
