// The whole haptic loop in one process, on a simulated clock: a device
// (SyntheticDevice) read by a ServoChannel, its poses carried to a Session,
// the session's force models carried back to the channel's inbox — each way
// through an in-memory link of a whole number of ticks. Nothing depends on
// the machine's clock or scheduling, so two runs that differ only in one
// setting (the deadbands, a delay) differ only by what that setting does.
//
// Each simulated millisecond: the channel senses (and sends the pose if its
// deadband lets it out); poses due at the server are offered to the session;
// the session ticks (and sends a model if its deadband lets it out); models
// due at the device reach the inbox; the channel actuates. With no delay a
// model answers the pose of the same tick.
#pragma once
#include <Eigen/Core>
#include <cstdint>
#include <map>
#include <string>
#include <vector>

#include "backends/synthetic_device.h"
#include "hapsim/runtime/session.h"
#include "hapsim/servo/servo_channel.h"

namespace hapsim::test {

struct HapticLoopConfig {
  std::string scene = "tissue_block";
  std::map<std::string, double> params;
  bridge::SyntheticScript script;
  double seconds = 1.0;            // simulated run length
  int one_way_delay_ticks = 0;     // each direction, whole servo periods
  service::SessionConfig session;  // its model deadband and pose extrapolation among others
  bridge::ChannelConfig channel;   // its pose deadband and safety chain among others
};

// One servo tick as the device saw it.
struct LoopTick {
  Eigen::Vector3d force_W_N = Eigen::Vector3d::Zero();      // commanded (after the safety chain)
  Eigen::Vector3d requested_W_N = Eigen::Vector3d::Zero();  // the held model's force at the stylus
  std::string phase;                                        // the script's phase
  double passivity_energy_J = 0.0;                          // the passivity observer's E after the tick
  bool passivity_acted = false;                             // its controller changed the force this tick
  bool pose_sent = false;
  bool model_taken = false;
};

struct HapticLoopRun {
  std::vector<LoopTick> ticks;
  std::uint64_t poses_sent = 0;
  std::uint64_t models_received = 0;
  bridge::SafetyCounters safety;  // the channel's chain at the end (watchdog events, passivity, ...)
};

HapticLoopRun RunHapticLoop(const HapticLoopConfig& config);

}  // namespace hapsim::test
