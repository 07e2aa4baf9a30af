// The results database: what a classroom produces (trials, score sheets,
// rosters, the recordings' index) and the live sessions to bring back after
// a restart, in one SQLite file (schema: docs/recording.md, "The results database").
//
// Writes never block the caller and never throw: they are queued (bounded,
// StoreOptions::queue_capacity) and one writer thread commits whatever is
// queued as one transaction, at most every batch_interval (50 ms). A write
// that finds the queue full is dropped, counted (dropped_writes) and logged.
// A database error on the writer thread is logged and counted
// (write_errors); the batch it hit is lost, the store carries on.
//
// Reads use their own read-only connection (WAL: they run while the writer
// commits) and see what is committed: Flush() first to read your own writes.
// Reads throw std::runtime_error on a database error (the caller decides).
//
// Durability: WAL with synchronous=NORMAL by default, so a kill -9 of the
// server loses only the writes not yet committed (queued in the last batch
// interval, plus the batch being committed), and nothing committed; a power
// loss may also lose the last commits unless fsync_every_commit is set.
#pragma once
#include <chrono>
#include <cstddef>
#include <cstdint>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "hapsim/store/schema.h"
#include "hapsim/store/stored_rows.h"

namespace hapsim::service {

struct StoreOptions {
  // false: synchronous=NORMAL (a commit survives the server's crash, not the
  // OS's); true: synchronous=FULL (every commit is fsynced; survives power loss).
  bool fsync_every_commit = false;
  std::size_t queue_capacity = 4096;             // writes waiting; beyond: dropped
  std::chrono::milliseconds batch_interval{50};  // the writer commits at most this often
  std::chrono::milliseconds busy_timeout{5000};  // waiting for another process's lock
  // Testing seams. `schema`: another build's migration steps (nullptr: this
  // build's). `before_batch`: runs on the writer thread before each batch's
  // transaction (a test holds the writer busy in it).
  const std::vector<SchemaStep>* schema = nullptr;
  std::function<void()> before_batch;
};

class ResultsStore {
 public:
  // Opens (creating if missing; its directory must exist) and migrates to the
  // newest schema. Throws std::runtime_error naming the path and what is
  // wrong: cannot open, not a hapsim results database, a schema newer than
  // this build's, a failed migration.
  static std::unique_ptr<ResultsStore> Open(const std::string& path, const StoreOptions& options = {});
  ~ResultsStore();  // commits everything queued, then stops the writer
  ResultsStore(const ResultsStore&) = delete;
  ResultsStore& operator=(const ResultsStore&) = delete;

  const std::string& path() const;
  int schema_version() const;  // the file's, after migration

  // Writes: any thread; queued, never blocking. Each returns false when the
  // queue was full and the write dropped.
  bool UpsertSession(const StoredSession& session);
  bool RemoveSession(const std::string& id);
  bool UpsertTrial(const StoredTrial& trial);
  // Call after ScoreBook::Submit accepted the sheet (a refused one is not kept).
  bool SaveScoreSheet(const std::string& session_id, const std::string& scene, const std::string& expert,
                      const std::vector<double>& indicators);
  // Inserts the entry, or widens its first/last seen to include now_unix_ms.
  bool NoteRoster(const std::string& class_name, const std::string& session_id, const std::string& trainee,
                  std::int64_t now_unix_ms);
  bool UpsertRecording(const StoredRecording& recording);
  bool MarkRecordingDeleted(const std::string& path);
  // Blocks until every write queued before the call is committed (or failed).
  void Flush();

  // Reads: any thread; what is committed.
  std::vector<StoredSession> Sessions() const;  // by creation time, then id
  // Those of the sessions `include` accepts (all when empty), by session id, run, trial.
  std::vector<StoredTrial> Trials(const std::function<bool(const std::string& session_id)>& include = {}) const;
  std::vector<StoredScoreSheet> ScoreSheets() const;  // in submission order (replay into ScoreBook::Submit)
  std::vector<StoredRosterEntry> Roster() const;      // by class, session, trainee
  // Every status, by session id, run, trial, path.
  std::vector<StoredRecording> Recordings(const std::function<bool(const std::string& session_id)>& include = {}) const;
  // Retention candidates: closed (ended, not deleted) recordings that ended before unix_ms, oldest first.
  std::vector<StoredRecording> RecordingsOlderThan(std::int64_t unix_ms) const;

  std::uint64_t dropped_writes() const;    // found the queue full
  std::uint64_t write_errors() const;      // sqlite errors on the writer thread
  std::uint64_t committed_writes() const;  // writes in committed batches

 private:
  struct Impl;
  explicit ResultsStore(std::unique_ptr<Impl> impl);
  std::unique_ptr<Impl> impl_;
};

}  // namespace hapsim::service
