// One device's share of a servo tick. The bridge's ServoLoop steps one
// channel; hapsim-load steps many on one thread. A tick is two calls:
//  Sense    read the device, fill the StylusPose for this tick and remember
//           its send time by seq (to turn an echoed seq into a round trip);
//  Actuate  take the newest force model from the device's inbox (capped at
//           the device's rendering limits, a jump blended in), record round
//           trip and model age, evaluate the local force model, pass it
//           through this device's ForceSafety and command the device.
// The caller sends pose() in between. Nothing allocates after construction.
// The servo sees core types only: the DDS side packs the pose it senses
// and has unpacked every model before it reaches the inbox (hapsim::wire).
#pragma once
#include <array>
#include <cstdint>
#include <string>

#include "hapsim/common/latest_value.h"
#include "hapsim/common/stats.h"
#include "hapsim/core/haptics/local_force_model.h"
#include "hapsim/servo/device.h"
#include "hapsim/servo/force_safety.h"
#include "hapsim/servo/model_delay.h"
#include "hapsim/servo/pose_deadband.h"
#include "hapsim/servo/servo_messages.h"

namespace hapsim::bridge {

struct ChannelConfig {
  std::uint32_t device_id = 1;
  double period_s = 0.001;             // servo period (the rise limit's dt)
  SafetyConfig safety;
  std::size_t stats_window = 1 << 17;  // recent samples kept for round-trip / model-age percentiles
  double model_delay_s = 0.0;          // measurement aid: every model held this long first (ModelDelay)
  PoseDeadbandConfig pose_deadband;    // which poses go out (default: every one)
  bool physics_reference = false;      // fill ChannelTick::physics_at_echo_W_N (for traces; one more evaluation)
};

// What the last tick did, for the caller's trace and pooled statistics.
struct ChannelTick {
  DeviceReading reading;
  Eigen::Vector3d requested_W_N = Eigen::Vector3d::Zero();  // from the local model (capped; before safety)
  Eigen::Vector3d blended_W_N = Eigen::Vector3d::Zero();    // handed to the chain: requested, or a model jump's blend
  Eigen::Vector3d force_W_N = Eigen::Vector3d::Zero();      // commanded (after safety)
  double model_age_s = -1.0;                                // stream gap: since the model used arrived; -1: none yet
  // The gap beyond the longest the server promised between models (its
  // deadband keep-alive, at most kLongestPromisedGapS; 0 for a server that
  // sends every tick): what the stream-gap watchdog judges.
  double model_overdue_s = -1.0;
  // How late the tissue is felt: the model's round trip (from when the
  // stylus was where the server stepped it — the pose it answers, moved on
  // by as long as the server held it) plus how overdue the stream is; -1:
  // none yet, +inf: it answers no pose this channel remembers (another
  // run's, or > 4 s old).
  double physics_age_s = -1.0;
  bool took_model = false;     // a new model arrived and was applied this tick
  // This tick's new model is the first to answer a remembered pose: the
  // round trip from sensing that pose, less the time the server held it
  // before the tick that stepped it (a model sent later for the same pose,
  // a keep-alive, comes from a tick that extrapolated it); else -1.
  double round_trip_s = -1.0;
  // When round_trip_s >= 0 and the config asks for it: the new model's force at the pose it echoes, as
  // the server sent it (before the device's caps). The model reproduces the
  // physics' tool force at the pose it was stepped with, so this is the force
  // the physics computed for that pose — the reference for transparency.
  Eigen::Vector3d physics_at_echo_W_N = Eigen::Vector3d::Zero();
};

struct ChannelCounters {
  std::uint64_t ticks = 0;             // completed Actuate calls
  std::uint64_t poses_due = 0;         // poses the deadband let out (pose_due() was true)
  std::uint64_t models_taken = 0;      // new models found in the inbox and applied (older ones are overwritten unseen)
  std::uint64_t echo_regressions = 0;  // models echoing an older pose than the one held: discarded (reordered)
  // Models of the followed server's sequence this device never rendered:
  // lost, or overwritten by a newer one before a tick took it (several
  // arrived within one tick: a clump after jitter). The newest always wins.
  std::uint64_t models_unused = 0;
  std::uint64_t first_echo_seq = 0, last_echo_seq = 0;  // valid when models_taken > 0
  double peak_force_N = 0.0;            // commanded
  double peak_force_pressing_N = 0.0;   // script phases press/hold
  double peak_force_withdrawn_N = 0.0;  // tip more than 1 mm above the surface after withdrawing
};

class ServoChannel {
 public:
  ServoChannel(HapticDevice* device, const ChannelConfig& config);

  // t_s: the device's time since its start (scripts and replays follow it).
  const DeviceReading& Sense(double t_s);
  // The same, sensed at now_ns on the clock models' received_ns use (the
  // steady clock above; a simulated one where a test runs the whole loop).
  const DeviceReading& Sense(double t_s, std::int64_t now_ns);
  const SensedPose& pose() const { return pose_; }
  // Should the pose just sensed go out (PoseDeadband)? The caller sends it only then.
  bool pose_due() const { return pose_due_; }
  const ChannelTick& Actuate(common::LatestValue<ReceivedModel>& inbox);

  const ChannelTick& last_tick() const { return tick_; }
  const ChannelCounters& counters() const { return counters_; }
  const SafetyCounters& safety_counters() const { return safety_.counters(); }
  WatchdogState watchdog() const { return safety_.state(); }
  double passivity_energy_J() const { return safety_.passivity_energy_J(); }  // the observer's E
  core::ContactState model_state() const { return have_model_ ? model_.model.state : core::ContactState::kFree; }
  std::uint32_t device_id() const { return pose_.device_id; }
  common::Percentiles RoundTrip() const { return round_trip_s_.Summary(); }
  common::Percentiles ModelAge() const { return model_age_s_.Summary(); }
  common::Percentiles PhysicsAge() const { return physics_age_s_.Summary(); }  // finite ages only

 private:
  // True when it took a new model, with tick_.requested_W_N already its force at the stylus.
  bool TakeNewestModel(common::LatestValue<ReceivedModel>& inbox);
  void RecordPeaks();

  // A server's promised gap between models counts for at most this long: a
  // bad promise must not blind the watchdog.
  static constexpr double kLongestPromisedGapS = 0.1;

  // Send time of each pose by seq; a model echoing a seq older than the ring
  // gets no round trip.
  static constexpr std::size_t kSentRing = 4096;

  HapticDevice* device_;
  double period_s_;
  ForceSafety safety_;
  std::int64_t warn_age_ns_;  // a held model younger than this is fresh: older arrivals are discarded
  SensedPose pose_;
  PoseDeadband pose_deadband_;
  bool physics_reference_;
  bool pose_due_ = false;
  std::uint64_t next_seq_ = 0;
  std::int64_t sensed_ns_ = 0;
  std::array<std::uint64_t, kSentRing> sent_seq_;
  std::array<std::int64_t, kSentRing> sent_ns_{};
  std::array<Eigen::Vector3d, kSentRing> sent_tip_W_m_, sent_velocity_W_m_per_s_;
  bool have_model_ = false;
  ReceivedModel model_;
  double promised_gap_s_ = 0.0;         // the held model's promised gap, at most kLongestPromisedGapS
  std::int64_t physics_sensed_ns_ = 0;  // when the pose the held model answers was sensed
  bool physics_known_ = false;          // ... and whether that pose is one this channel remembers
  ModelDelay delay_;
  ChannelTick tick_;
  ChannelCounters counters_;
  common::SampleWindow round_trip_s_, model_age_s_, physics_age_s_;
};

}  // namespace hapsim::bridge
