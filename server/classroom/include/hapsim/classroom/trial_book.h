// Every trial's automatic metrics, kept for the per-class CSV export
// (GetTrials, `hapsim-ctl trials CLASS`). Fed by the frame pump: each pass it
// takes every session's running-trial metrics and any trial a reset ended
// (from its SessionTrials);
// a session gone from the table ends its running trial ("closed").
// Bounded: the oldest ended trials are dropped beyond kMaxTrials.
#pragma once
#include <cstdint>
#include <deque>
#include <functional>
#include <map>
#include <memory>
#include <mutex>
#include <string>
#include <vector>

#include "hapsim/classroom/session_trials.h"
#include "hapsim/classroom/trial_tracker.h"
#include "hapsim/runtime/session_registry.h"

namespace hapsim::service {

struct TrialRecord {
  std::string session_id, trainee, scene;
  std::vector<std::string> layer_names;
  TrialTargets targets;
  TrialStats stats;
  std::string end;  // "reset", "closed", "running", or "interrupted" (the server stopped and did not bring it back)
};

class TrialBook {
 public:
  static constexpr std::size_t kMaxTrials = 10000;

  // Frame pump thread only (a FramePump pass listener).
  void Observe(const SessionTable& sessions);

  // Where trials go to be kept (the results database): every ended trial,
  // and each running one at most once per `running_every_s`. Called on the
  // frame pump's thread; must not block. Set before the pump starts.
  void SetSink(std::function<void(const TrialRecord&)> sink, double running_every_s = 1.0);
  // Trials of earlier server runs (from the database), oldest first, shown
  // as ended ones. Call before the pump starts.
  void Preload(std::vector<TrialRecord> ended);

  // Any thread: ended trials, then the running ones, of the sessions
  // `include` accepts (all when empty), in session-id then trial order.
  std::vector<TrialRecord> Trials(const std::function<bool(const std::string&)>& include = {}) const;

 private:
  struct Running {
    std::shared_ptr<Session> session;
    TrialRecord record;
    std::int64_t sunk_ns = 0;  // when the sink last had this trial
    std::uint64_t seen_pass = 0;  // the last Observe pass that found its session in the table
  };
  static TrialRecord Describe(const Session& session, const SessionTrials& trials, const TrialStats& stats,
                              const char* end);
  void AddEndedLocked(TrialRecord record);

  mutable std::mutex mutex_;
  std::map<const Session*, Running> running_;
  std::uint64_t observe_passes_ = 0;  // Observe's pass count: marks which running trials' sessions are present
  std::deque<TrialRecord> ended_;
  std::function<void(const TrialRecord&)> sink_;
  std::int64_t sink_running_every_ns_ = 1'000'000'000;
};

// CSV, one row per trial; `score_of` (may be empty) gives a session's
// current expert score ("" if unscored). Columns in docs/classroom.md.
std::string FormatTrialsCsv(const std::vector<TrialRecord>& trials,
                            const std::function<std::string(const std::string&)>& score_of = {});

}  // namespace hapsim::service
