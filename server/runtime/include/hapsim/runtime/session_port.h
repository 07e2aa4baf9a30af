// A session's link to its device: force models out, poses in. The DDS
// adapter (ServerDds) opens one per session, in the session's own DDS
// partition, so each bridge receives only its session's models; tests use
// in-memory ports. The session hands over plain data (ForceModelMessage);
// only the adapter knows the wire format.
#pragma once
#include <cstdint>
#include <memory>
#include <string>

#include <Eigen/Core>

#include "hapsim/core/haptics/local_force_model.h"

namespace hapsim::service {

class Session;

// What one tick sends to the device that owns the session.
struct ForceModelMessage {
  std::uint32_t device_id = 0;      // the owning device (the wire key)
  std::uint64_t seq = 0;            // per session, +1 each model sent
  std::uint64_t echo_pose_seq = 0;  // seq of the pose this tick stepped with (round trip)
  std::int64_t t_server_ns = 0;     // server steady clock when the tick wrote it
  // How long the session had held that pose when this tick stepped (0: it
  // arrived for this tick; since then the tool was extrapolated from it).
  std::int64_t echo_pose_held_ns = 0;
  double next_model_within_s = 0.0;  // the longest the session leaves between models (0: every tick)
  core::LocalForceModel model;      // what the bridge renders until the next one
  Eigen::Vector3d tool_force_W_N = Eigen::Vector3d::Zero();  // the physics' own force at this tick [N]
};

class SessionPort {
 public:
  virtual ~SessionPort() = default;
  // Tick workers (one at a time per session). Must not block or allocate.
  // False if the write failed.
  virtual bool WriteForceModel(const ForceModelMessage& message) = 0;
  // Control thread: poses start reaching `session` (after it is published in
  // the registry's table) / stop (before it leaves the tick pool).
  virtual void StartReceiving(Session* /*session*/) {}
  virtual void StopReceiving() {}
};

class SessionTransport {
 public:
  virtual ~SessionTransport() = default;
  // Opens the endpoints of a new session; throws on a transport failure.
  virtual std::shared_ptr<SessionPort> Open(const std::string& session_id) = 0;
};

}  // namespace hapsim::service
