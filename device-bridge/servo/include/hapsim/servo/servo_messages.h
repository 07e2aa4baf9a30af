// What crosses between a servo tick and the bridge's DDS side, in core
// types: the DDS side packs the pose and has unpacked the model.
#pragma once
#include <cstdint>

#include "hapsim/core/haptics/local_force_model.h"
#include "hapsim/core/scenes/scene.h"  // ToolInput

namespace hapsim::bridge {

// A force model as a DDS receive thread took it, unpacked.
struct ReceivedModel {
  core::LocalForceModel model;        // what to render until the next one
  std::uint64_t seq = 0;              // the server's, +1 per model of the session
  std::uint64_t echo_pose_seq = 0;    // seq of the pose the server stepped with
  std::uint64_t server_instance = 0;  // which server sent it
  std::int64_t received_ns = 0;       // this process's steady clock at arrival
  // How long the server had held that pose when it stepped (it extrapolated
  // the tool meanwhile): the model's physics is of the stylus this much
  // after the pose was sensed.
  std::int64_t echo_pose_held_ns = 0;
  // The server's promise: the next model comes within this (its model
  // keep-alive under deadband coding; 0: every tick).
  double next_model_within_s = 0.0;
};

// A pose as one servo tick sensed it, for the DDS side to send.
struct SensedPose {
  core::ToolInput tool;
  std::uint32_t device_id = 0;
  std::uint64_t seq = 0;         // +1 per tick of this device
  std::int64_t t_device_ns = 0;  // this process's steady clock when sensed
};

}  // namespace hapsim::bridge
