// The frame pump: one thread that collects each session's newest snapshot and
// offers it to that session's viewer streams (which send it or skip it; see
// ViewerLink). It polls every poll_period; snapshots are produced by the
// session ticks at the frame rate.
#pragma once
#include <atomic>
#include <thread>

#include "hapsim/service/session_registry.h"

namespace hapsim::service {

class FramePump {
 public:
  FramePump(SessionRegistry* registry, double poll_period_s = 0.002);
  ~FramePump();
  void Start();
  void Stop();
  // One pass over all sessions (also used by tests).
  void PumpOnce();

 private:
  SessionRegistry* registry_;
  double poll_period_s_;
  std::atomic<bool> stop_{false};
  std::thread thread_;
};

}  // namespace hapsim::service
