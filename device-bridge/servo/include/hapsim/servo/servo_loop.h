// The bridge's 1 kHz servo loop: one ServoChannel (read the device, evaluate
// the newest local force model, ForceSafety, command the device) on a
// DeadlineTicker - or, for a device whose driver runs its own servo
// scheduler, on that scheduler's ticks - handing each pose to the DDS
// thread. No DDS call, lock, allocation or I/O happens inside a tick: poses
// and models cross through latest-value mailboxes, and the trace is a
// buffer reserved before the loop starts and written after it ends.
#pragma once
#include <atomic>
#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "hapsim/servo/servo_channel.h"

namespace hapsim::bridge {

struct ServoConfig {
  std::uint32_t device_id = 1;
  std::string session = "demo";
  double rate_hz = 1000.0;         // own-servo devices: their scheduler's rate (the chain's dt)
  double run_seconds = 0.0;        // 0: until stop is set
  SafetyConfig safety;
  double model_delay_s = 0.0;      // measurement aid: see ModelDelay
  std::size_t trace_capacity = 0;  // rows of trace to keep (0: none)
  PoseDeadbandConfig pose_deadband;  // which poses go out (default: every one)
  bool stop_when_script_finishes = true;
};

struct TraceRow {
  double t_s;
  Eigen::Vector3d tip_W_m;
  Eigen::Quaterniond orientation_W;
  Eigen::Vector3d force_W_N;      // commanded (after safety)
  Eigen::Vector3d requested_W_N;  // from the local model (before safety)
  double model_age_ms;            // stream gap; -1: no model yet
  double physics_age_ms;          // round trip + gap (ChannelTick::physics_age_s); -1: no model yet, inf: not ours
  std::uint64_t echo_pose_seq;
  const char* phase;
  std::uint8_t model_state;
  WatchdogState watchdog;
  std::uint64_t pose_seq;  // the pose this tick sensed
  bool pose_sent;          // ...and sent (the pose deadband let it out)
  bool model_taken;        // a new force model was applied this tick
  // The physics' force for this tick's pose, filled in when the model that
  // echoes it arrives (ChannelTick::physics_at_echo_W_N); NaN if none did.
  Eigen::Vector3d physics_W_N;
};

struct ServoReport {
  double elapsed_s = 0.0;
  // Device time of the first tick that had a force model (-1: none came):
  // until then the stylus is free (zero force) while the bridge discovers
  // its server over DDS.
  double first_model_s = -1.0;
  common::Percentiles period_error_s;  // |actual period - nominal| (own-servo devices: between successive ticks' t)
  common::Percentiles model_age_s;     // stream gap of the model used, per tick
  common::Percentiles physics_age_s;   // physics age of the model used, per tick (round trip + gap)
  common::Percentiles round_trip_s;    // pose sent -> model echoing it received
  ChannelCounters channel;              // ticks, models taken, echoed seqs, force peaks
  SafetyCounters safety;
  WatchdogState final_watchdog = WatchdogState::kNoModel;
  std::vector<TraceRow> trace;
};

class ServoLoop {
 public:
  ServoLoop(HapticDevice* device, ServoConfig config, common::LatestValue<SensedPose>* pose_out,
            common::LatestValue<ReceivedModel>* model_in, std::function<void()> wake_io);
  // Runs on the calling thread (or, for a device that RunsOwnServo, on
  // the thread its driver calls back on) until stop, run_seconds, or the
  // script ends.
  ServoReport Run(const std::atomic<bool>& stop);

 private:
  // One tick at time t [s]; false ends the run.
  bool Tick(ServoChannel& channel, double t_s, const std::atomic<bool>& stop, ServoReport* report);
  void RunOnTicker(ServoChannel& channel, const std::atomic<bool>& stop, ServoReport* report);
  void RunOnDeviceServo(ServoChannel& channel, const std::atomic<bool>& stop, ServoReport* report);

  HapticDevice* device_;
  ServoConfig config_;
  common::LatestValue<SensedPose>* pose_out_;
  common::LatestValue<ReceivedModel>* model_in_;
  std::function<void()> wake_io_;
};

// Writes the trace as CSV (t_s,x_m,y_m,z_m,qw,qx,qy,qz,fx_N,fy_N,fz_N,
// req_fx_N,req_fy_N,req_fz_N,model_age_ms,echo_pose_seq,model_state,watchdog,phase,
// pose_seq,phys_fx_N,phys_fy_N,phys_fz_N (the physics force for the row's pose, nan if no model echoed it),
// pose_sent,model_taken (0/1: what crossed the network this tick),physics_age_ms);
// its first 8 columns are a pose log the replay backend can play.
bool WriteTraceCsv(const std::string& path, const std::vector<TraceRow>& rows);

}  // namespace hapsim::bridge
