// Which synthetic devices hapsim-load runs: device i has id
// first_device_id + i, drives session `<prefix><i>` (or sessions[i] when a
// list is given), runs the common script with seed base + i, and reads it
// at a phase offset i * phase_spread_s / N, so the devices press and
// withdraw at staggered times instead of in lockstep.
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
};

struct LoadDevicePlan {
  std::uint32_t device_id = 0;
  std::string session;
  SyntheticScript script;
  double phase_s = 0.0;  // the device reads its script at t + phase_s
};

// Throws std::invalid_argument for a bad count, a malformed or repeated
// session id ([A-Za-z0-9_-]{1,63}) or a negative spread.
std::vector<LoadDevicePlan> PlanDevices(const LoadPlanOptions& options);

// "a,b,,c" -> {"a", "b", "c"}
std::vector<std::string> SplitCommaList(const std::string& text);

}  // namespace hapsim::bridge
