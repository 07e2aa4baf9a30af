// The server's recorder: one thread that writes every session's trials to
// disk, off the tick. Each pass (every flush interval) it drains each
// session's queue and appends the ticks as one compressed block per
// session, plus the checkpoints among them, to the trial's file:
//
//   DIR/SESSION/RUN-tNNNN.hrec      one file per trial (a reset starts the next)
//
// What a kill -9 of the server loses: the ticks still queued, at most one
// flush interval (50 ms by default) plus one pass's writing. A power loss
// also loses what the OS had not written: set fsync_interval_ms to bound it.
//
// A session's recording ends (its end record written) when the session is
// gone — closed, and its last reference dropped. Stop() (the server shutting
// down) writes what is queued and leaves the trials open: a restarted
// server brings the sessions back and appends to the same files.
#pragma once
#include <condition_variable>
#include <cstdint>
#include <functional>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <thread>
#include <vector>

#include "hapsim/recording/recording_file.h"
#include "hapsim/recording/session_recorder.h"

namespace hapsim::service {

struct RecordingOptions {
  std::string directory;                        // trials go under it (created if missing)
  std::uint32_t checkpoint_every_ticks = 1000;  // a state hash every second of a 1 kHz trial
  std::int64_t flush_interval_ms = 50;          // writes reach the OS at least this often
  std::int64_t fsync_interval_ms = 0;           // 0: never fsync (survives a process crash, not a power loss)
  std::size_t queue_ticks = 4096;               // per session: 4 s at 1 kHz before ticks are lost
};

// A trial file as the writer sees it (for the results database's index).
struct RecordingEvent {
  enum class Kind { kOpened, kProgress, kClosed, kBroken } kind = Kind::kOpened;
  std::string path, session_id, run_id, scene, owner, class_name;
  std::uint64_t trial = 0;
  std::int64_t started_unix_ms = 0;
  std::int64_t ended_unix_ms = 0;  // kClosed only
  std::uint64_t ticks = 0;         // recorded so far
  std::uint64_t bytes = 0;
  std::string problem;  // kBroken: why the trial's recording stopped
};

struct RecordingStats {
  std::uint64_t ticks_written = 0;
  std::uint64_t ticks_lost = 0;  // found a full queue (summed over sessions, also gone ones)
  std::uint64_t bytes_written = 0;
  std::uint64_t write_errors = 0;
  std::uint64_t open_trials = 0;
};

class RecordingService {
 public:
  // on_event runs on the writer thread (it must not call back into the service).
  RecordingService(RecordingOptions options, std::function<void(const RecordingEvent&)> on_event = {});
  ~RecordingService();
  RecordingService(const RecordingService&) = delete;
  RecordingService& operator=(const RecordingService&) = delete;

  // A new session's recorder (its TickListener). `trial`, `first_tick`:
  // where its ticks start; `resume`: a restored session's open trial file.
  std::shared_ptr<SessionRecorder> Attach(RecordedSession who, std::uint64_t first_tick = 0,
                                          std::optional<RecordingResume> resume = std::nullopt);
  // Writes everything queued so far (tests, and before a planned kill).
  void Flush();
  // Final pass: writes what is queued and stops the thread; trials stay open.
  void Stop();
  RecordingStats stats() const;
  const RecordingOptions& options() const { return options_; }

 private:
  struct Track;  // one session's recording state on the writer thread
  void Run();
  void Pass(bool final_pass);
  void WriteRecords(Track& track, const std::vector<TickRecord>& records);
  void OpenTrial(Track& track, const TickInput& first);
  void EndTrial(Track& track, bool clean);
  void Break(Track& track, const std::string& problem);
  bool Write(Track& track, std::span<const std::uint8_t> bytes);
  void Emit(const Track& track, RecordingEvent::Kind kind, const std::string& problem = {});

  RecordingOptions options_;
  std::function<void(const RecordingEvent&)> on_event_;
  mutable std::mutex mutex_;  // guards tracks_' list, stats_, stop_
  std::condition_variable wake_;
  std::vector<std::unique_ptr<Track>> tracks_;
  std::vector<std::unique_ptr<Track>> attached_;  // added since the last pass
  RecordingStats stats_;
  bool stop_ = false;
  std::uint64_t flush_requested_ = 0, flush_done_ = 0;
  std::condition_variable flushed_;
  std::int64_t last_sync_ms_ = 0;
  TickBlockEncoder encoder_;  // writer thread only
  std::thread thread_;
};

// Milliseconds since the Unix epoch (the files' and database's wall clock).
std::int64_t UnixNowMs();

}  // namespace hapsim::service
