// The frame pump: one thread that, every poll_period, has the ViewerHub take
// each session's newest snapshot and offer it to that session's viewer
// streams (which send it or skip it; see ViewerLink). Snapshots are produced
// by the session ticks at the frame rate.
#pragma once
#include <atomic>
#include <thread>

#include "hapsim/service/session_registry.h"
#include "hapsim/service/trial_book.h"
#include "hapsim/service/viewer_hub.h"

namespace hapsim::service {

class FramePump {
 public:
  // trials (may be null): fed each pass with the sessions' trial metrics.
  FramePump(const SessionRegistry* registry, ViewerHub* hub, TrialBook* trials = nullptr,
            double poll_period_s = 0.002);
  ~FramePump();
  void Start();
  void Stop();
  // One pass over all sessions (also used by tests).
  void PumpOnce();

 private:
  const SessionRegistry* registry_;
  ViewerHub* hub_;
  TrialBook* trials_;
  double poll_period_s_;
  std::atomic<bool> stop_{false};
  std::thread thread_;
};

}  // namespace hapsim::service
