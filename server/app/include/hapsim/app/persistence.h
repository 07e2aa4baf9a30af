// What a server keeps in its data directory (--data-dir) so that nothing a
// class did is lost when it stops, crashes or restarts:
//
//   DIR/lock                    held while a server uses DIR (one server per directory)
//   DIR/results.sqlite          the results database: trials, score sheets,
//                               rosters, the recordings' index, the live sessions
//   DIR/recordings/SESSION/RUN-tNNNN.hrec   one trial recording per file
//
// At start it brings back what the last run left: the trials and score
// sheets (shown and exported as before), and every session that was live —
// its scene rebuilt and its recorded inputs re-run through the same steps,
// so it goes on from exactly the state its recording reached (checked
// against the recorded state hashes), in the same trial, appending to the
// same file. Bridges and viewers reconnect to it as to any session.
#pragma once
#include <cstdint>
#include <map>
#include <memory>
#include <mutex>
#include <string>
#include <vector>

#include "hapsim/classroom/access_policy.h"
#include "hapsim/classroom/score_book.h"
#include "hapsim/classroom/session_trials.h"
#include "hapsim/classroom/trial_book.h"
#include "hapsim/recording/recording_service.h"
#include "hapsim/runtime/session_registry.h"
#include "hapsim/store/results_store.h"

namespace hapsim::service {

enum class RecordPolicy { kNone, kClass, kAll };  // which sessions' trials are recorded
bool ParseRecordPolicy(const std::string& text, RecordPolicy* out);
const char* RecordPolicyName(RecordPolicy policy);

struct PersistenceOptions {
  std::string data_dir;
  RecordPolicy record = RecordPolicy::kClass;  // class sessions (those of the class config)
  RecordingOptions recording;                  // its directory is DIR/recordings
  bool fsync_database = false;                 // sqlite synchronous=FULL instead of NORMAL
  double retention_days = 90.0;                // closed recordings older than this are deleted (0: kept)
};

class Persistence final : public SessionListener {
 public:
  // Takes DIR's lock, opens the database and starts the recorder. Throws
  // std::runtime_error (what and where) when DIR cannot be used or another
  // server holds it. `next` hears of every close after this does.
  Persistence(PersistenceOptions options, const AccessPolicy* policy, SessionListener* next);
  ~Persistence() override;

  // What follows each new session's ticks: its trials and, when recorded,
  // its recorder; the session is entered in the database.
  TickListenerFactory ListenerFactory();
  // Before the server serves: the trials and score sheets of earlier runs
  // into the books (which then keep the database up to date), and the
  // sessions that were live brought back. Returns their ids.
  std::vector<std::string> BringBack(SessionRegistry& registry, TrialBook& trials, ScoreBook& scores);
  // Deletes closed recordings past the retention age (at start, then from the
  // frame pump at most once an hour).
  void ApplyRetention();
  void MaybeApplyRetention();

  // A session closed by a client leaves the database; one closed because the
  // server stops stays there, to come back.
  void OnSessionClosed(Session& session, CloseReason why) override;
  // Writes what is queued (recordings and database) and stops the recorder.
  void Stop();

  ResultsStore& store() { return *store_; }
  RecordingService& recording() { return *recording_; }
  const std::string& recordings_dir() const { return options_.recording.directory; }

 private:
  bool Recorded(const std::string& session_id) const;
  std::shared_ptr<TickListener> ListenersFor(const SessionConfig& config);
  bool RestoreOne(SessionRegistry& registry, const StoredSession& stored);
  void OnRecordingEvent(const RecordingEvent& e);
  void SinkTrial(const TrialRecord& record);

  PersistenceOptions options_;
  const AccessPolicy* policy_;
  SessionListener* next_;
  int lock_fd_ = -1;
  std::unique_ptr<ResultsStore> store_;
  std::unique_ptr<RecordingService> recording_;
  std::int64_t last_retention_ms_ = 0;

  std::mutex mutex_;                               // guards the maps below (gRPC, pump and writer threads)
  std::map<std::string, StoredSession> sessions_;  // live ones, as in the database
  // (session id, trial) -> its recording file, for the trials table.
  std::map<std::pair<std::string, std::uint64_t>, std::string> trial_files_;
  std::map<std::string, std::string> run_of_;  // session id -> its run id (also after close)
};

}  // namespace hapsim::service
