// hapsim-load's servo thread: every device of the plan as a SyntheticDevice
// with its own ServoChannel (and so its own ForceSafety chain), all stepped
// by one thread on one DeadlineTicker at the servo rate. Per tick and
// device: sense, write the pose, take the newest model from the device's
// inbox (filled by the receive thread through the ModelRouter), render.
// One thread instead of one per device keeps the load generator's own
// wake-ups from competing with the server it measures. With device clocks
// of their own (the plan's clock phases and rates, DeviceClocks) it wakes
// for each device's tick and steps the devices due then; else it steps all
// of them together once per period. Nothing allocates
// inside a tick (our part; see DeviceDds::WritePose for DDS).
#pragma once
#include <atomic>
#include <functional>
#include <memory>
#include <vector>

#include "backends/synthetic_device.h"
#include "hapsim/bridge/model_router.h"
#include "hapsim/common/log_histogram.h"
#include "hapsim/load/device_clocks.h"
#include "hapsim/load/load_plan.h"
#include "hapsim/load/load_report.h"
#include "hapsim/servo/servo_channel.h"

namespace hapsim::bridge {

struct LoadRunConfig {
  double rate_hz = 1000.0;
  double run_seconds = 0.0;  // 0: until stop is set
  double interval_s = 0.0;   // > 0: also report percentiles per interval of this length
  SafetyConfig safety;
  PoseDeadbandConfig pose_deadband;  // which poses each device sends (default: every one)
};

// Sends one pose to the server; false when refused (counted per device).
using PoseWriter = std::function<bool(const SensedPose&)>;

// Samples kept per device for its percentiles: the whole run if it is
// bounded (within a budget over all devices), else the last minute or so.
std::size_t StatsWindowPerDevice(double run_seconds, double rate_hz, std::size_t devices);

class LoadRunner {
 public:
  // router: built for the same plan (device i is router inbox i). Throws
  // std::invalid_argument for a script the synthetic device rejects.
  LoadRunner(const std::vector<LoadDevicePlan>& plan, const LoadRunConfig& config, ModelRouter* router,
             PoseWriter write_pose);
  // Runs on the calling thread until stop or run_seconds.
  LoadReport Run(const std::atomic<bool>& stop);

 private:
  void StepDevice(std::size_t i, double t_s);
  // The servo loops: all devices at once per period, or each on its own clock.
  void RunInLockstep(const std::atomic<bool>& stop, ServoThreadReport* servo);
  void RunOnDeviceClocks(const std::atomic<bool>& stop, ServoThreadReport* servo);
  // Closes the interval ending at end_s (servo thread; no allocation).
  void CloseInterval(double end_s);
  // Closes the current interval if it ended by t_s (one per wake: a wake
  // never comes a whole interval late).
  void CloseIntervalIfEnded(double t_s);
  LoadReport Report(double elapsed_s) const;

  LoadRunConfig config_;
  ModelRouter* router_;
  PoseWriter write_pose_;
  std::vector<LoadDevicePlan> plan_;
  std::vector<std::unique_ptr<SyntheticDevice>> devices_;
  std::vector<ServoChannel> channels_;
  std::vector<std::uint64_t> poses_sent_, write_failures_;
  common::SampleWindow pooled_round_trip_s_, pooled_model_age_s_, pooled_physics_age_s_;
  common::LogHistogram interval_round_trip_s_, interval_model_age_s_;
  std::vector<LoadInterval> intervals_;  // reserved up front
  std::uint64_t intervals_dropped_ = 0;
  double interval_end_s_ = 0.0;
};

}  // namespace hapsim::bridge
