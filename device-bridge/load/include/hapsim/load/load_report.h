// What hapsim-load measured: per device, pooled over all devices, the servo
// thread itself, and (when asked) the server's own counters of each session.
#pragma once
#include <cstdint>
#include <string>
#include <vector>

#include "hapsim/common/stats.h"
#include "hapsim/servo/force_safety.h"

namespace hapsim::bridge {

// Poses out and models back: of one device, or of all devices (counts
// summed, percentiles pooled).
struct LoadFlow {
  std::uint64_t poses_sent = 0;
  std::uint64_t pose_write_failures = 0;  // samples DDS refused
  double pose_rate_hz = 0.0;
  std::uint64_t models_received = 0;  // routed by the receive thread
  std::uint64_t models_used = 0;      // taken by the servo thread (newest per tick; older ones overwritten)
  std::uint64_t echo_regressions = 0;
  std::uint64_t models_unused = 0;   // of the server's sequence, never rendered (lost or overwritten)
  common::Percentiles round_trip_s;  // pose sensed -> model echoing it received
  common::Percentiles model_age_s;   // stream gap of the model rendered, per tick
  common::Percentiles physics_age_s;  // its physics age (round trip + gap), per tick
  SafetyCounters safety;              // warnings/fades/disarms are events, clamps are ticks
};

struct LoadDeviceReport {
  std::uint32_t device_id = 0;
  std::string session;
  LoadFlow flow;
  std::uint64_t first_echo_seq = 0, last_echo_seq = 0;  // valid when flow.models_used > 0
  WatchdogState final_watchdog = WatchdogState::kNoModel;
  double peak_force_N = 0.0;
};

struct LoadTotals {
  std::size_t devices = 0;
  std::size_t devices_with_models = 0;
  std::size_t devices_disarmed = 0;  // devices whose watchdog disarmed at least once
  LoadFlow flow;
};

// The one thread that steps every device: if it cannot hold its rate, the
// figures above measure the load generator, not the server.
struct ServoThreadReport {
  std::uint64_t ticks = 0;         // wakes: one per period in lockstep, else one per batch of due device ticks
  std::uint64_t reanchors = 0;     // stalls longer than 10 periods
  common::Percentiles lateness_s; // wake behind its deadline
  common::Percentiles work_s;     // stepping all devices in one tick
};

// A session's counters as the server reports them (SessionService).
struct ServerSessionStats {
  std::string session_id;
  std::string error;  // non-empty: the server did not report this session
  std::uint64_t ticks = 0, late_ticks = 0, device_clocked_ticks = 0;
  std::uint64_t poses_received = 0, poses_rejected = 0, poses_from_other_devices = 0, force_models_sent = 0;
  std::uint32_t owning_device_id = 0;
  bool device_streaming = false;
  double max_tick_lateness_s = 0.0;
};

// Pooled over all devices for one stretch of the run (--interval-s): how
// the round trip and the model age change over a long run. Percentiles are
// binned (common::LogHistogram, bins 2 % wide: never below the exact value,
// at most 2 % above); count, max and mean are exact.
struct LoadInterval {
  double end_s = 0.0;  // run time at the interval's end
  common::Percentiles round_trip_s;
  common::Percentiles model_age_s;
};

struct LoadReport {
  double rate_hz = 0.0;
  double elapsed_s = 0.0;
  ServoThreadReport servo;
  std::vector<LoadDeviceReport> devices;
  LoadTotals total;
  std::uint64_t models_for_unknown_devices = 0;  // other device ids on the domain
  std::uint64_t models_for_other_sessions = 0;   // our device ids, another session
  std::uint64_t models_from_other_servers = 0;   // our devices and sessions, but not the server each follows
  std::vector<ServerSessionStats> server;        // empty: not fetched
  std::vector<LoadInterval> intervals;           // empty: --interval-s not given
  std::uint64_t intervals_dropped = 0;           // past the space reserved for them
};

// Sums (and counts) the devices into a LoadTotals; the pooled percentiles
// are left for the caller, who holds the pooled samples.
LoadTotals SumDevices(const std::vector<LoadDeviceReport>& devices);

}  // namespace hapsim::bridge
