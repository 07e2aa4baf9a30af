// What a session's tick hands to its recording: every tick's TickInput, and
// the scene's state hash after the ticks that are checkpoints (every
// `checkpoint_every_ticks` of a trial, counted from the trial's first tick).
// A TickListener on the tick worker: it never blocks and never allocates
// (a bounded ring; a tick that finds it full is counted as lost, and the
// writer marks the trial's recording as broken there).
#pragma once
#include <atomic>
#include <cstdint>
#include <string>

#include "hapsim/recording/recording_format.h"
#include "hapsim/recording/tick_ring.h"
#include "hapsim/runtime/session.h"
#include "hapsim/runtime/tick_listener.h"

namespace hapsim::service {

// Who the recorded session is, for the files' headers.
struct RecordedSession {
  std::string session_id;
  std::string run_id;
  std::string scene;
  std::map<std::string, double> params;
  std::string owner;
  std::string class_name;
  double tick_period_s = 0.001;
};

// Where a restored session's recording goes on: the trial's file (cut back
// to its last good record and appended to), as its reader found it.
struct RecordingResume {
  std::string path;
  std::uint64_t valid_bytes = 0;
  RecordingHeader header;       // the file's: its trial, first tick, start time
  std::uint64_t next_tick = 0;  // the first tick not in the file
};

class SessionRecorder final : public TickListener {
 public:
  SessionRecorder(RecordedSession who, std::size_t queue_ticks, std::uint32_t checkpoint_every_ticks,
                  std::uint64_t trial_first_tick = 0)
      : who_(std::move(who)),
        checkpoint_every_(checkpoint_every_ticks),
        ring_(queue_ticks),
        trial_first_tick_(trial_first_tick) {}

  // Tick worker.
  void OnTick(const TickOutcome& tick) override;

  // Writer.
  std::size_t Drain(std::vector<TickRecord>* out) { return ring_.Drain(out); }
  const RecordedSession& who() const { return who_; }
  std::uint32_t checkpoint_every_ticks() const { return checkpoint_every_; }

  // Any thread: ticks that found the queue full.
  std::uint64_t lost_ticks() const { return lost_.load(std::memory_order_relaxed); }

 private:
  RecordedSession who_;
  std::uint32_t checkpoint_every_;
  TickRing ring_;
  std::uint64_t trial_first_tick_;  // tick worker only
  std::atomic<std::uint64_t> lost_{0};
};

}  // namespace hapsim::service
