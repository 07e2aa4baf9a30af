// The frame pump: one thread that, every poll_period, has the ViewerHub take
// each session's newest snapshot and offer it to that session's viewer
// streams (which send it or skip it; see ViewerLink). Snapshots are produced
// by the session ticks at the frame rate. Whatever else wants a regular
// look at every session off the tick (the classroom's trial book) joins as
// a pass listener. While no session has a viewer it passes every
// idle_poll_period instead (still within half a 60 Hz frame): each pass
// wakes a thread, which costs the tick's core more than the pass's work.
#pragma once
#include <atomic>
#include <functional>
#include <thread>

#include "hapsim/runtime/session_registry.h"
#include "hapsim/streaming/viewer_hub.h"

namespace hapsim::service {

class FramePump {
 public:
  // Called after each pass with the table it pumped (on the pump's thread).
  using PassListener = std::function<void(const SessionTable&)>;

  FramePump(const SessionRegistry* registry, ViewerHub* hub, PassListener after_pass = {}, double poll_period_s = 0.002,
            double idle_poll_period_s = 0.008);
  ~FramePump();
  void Start();
  void Stop();
  // One pass over all sessions (also used by tests).
  void PumpOnce();

 private:
  const SessionRegistry* registry_;
  ViewerHub* hub_;
  PassListener after_pass_;
  double poll_period_s_, idle_poll_period_s_;
  std::atomic<bool> stop_{false};
  std::thread thread_;
};

}  // namespace hapsim::service
