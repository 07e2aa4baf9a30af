// The store's reads: one read-only connection, one query at a time (a
// mutex). In WAL mode it reads the last committed state while the writer
// commits the next; it never sees a half-written batch.
#pragma once
#include <cstdint>
#include <functional>
#include <mutex>
#include <string>
#include <vector>

#include "hapsim/store/stored_rows.h"
#include "sqlite_handle.h"

namespace hapsim::service::store_internal {

class StoreReader {
 public:
  using SessionFilter = std::function<bool(const std::string& session_id)>;
  StoreReader(DbHandle db, std::string path) : db_(std::move(db)), path_(std::move(path)) {}

  // Each throws std::runtime_error naming the file on a database error or a malformed row.
  std::vector<StoredSession> Sessions() const;
  std::vector<StoredTrial> Trials(const SessionFilter& include) const;
  std::vector<StoredScoreSheet> ScoreSheets() const;
  std::vector<StoredRosterEntry> Roster() const;
  std::vector<StoredRecording> Recordings(const SessionFilter& include) const;
  std::vector<StoredRecording> RecordingsOlderThan(std::int64_t unix_ms) const;

 private:
  // Runs `sql` (binding `bind`) and calls `row` on each result row, under the mutex.
  void Query(const std::string& sql, const char* what, const std::function<void(Statement&)>& bind,
             const std::function<void(const Statement&)>& row) const;

  DbHandle db_;
  std::string path_;
  mutable std::mutex mutex_;
};

}  // namespace hapsim::service::store_internal
