// A session's link to its device: force models out, poses in. The DDS
// adapter (ServerDds) opens one per session, in the session's own DDS
// partition, so each bridge receives only its session's models; tests use
// in-memory ports.
#pragma once
#include <memory>
#include <string>

#include "haptics.h"

namespace hapsim::service {

class Session;

class SessionPort {
 public:
  virtual ~SessionPort() = default;
  // Tick workers (one at a time per session). Must not block. False if the
  // write failed.
  virtual bool WriteForceModel(const hapsim_dds_LocalForceModel& model) = 0;
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
