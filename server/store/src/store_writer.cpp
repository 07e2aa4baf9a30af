#include "store_writer.h"

#include <spdlog/spdlog.h>

#include "hapsim/common/thread_setup.h"
#include "hapsim/store/text_codecs.h"
#include "row_codec.h"

namespace hapsim::service::store_internal {

StoreWriter::StoreWriter(DbHandle db, std::string path, WriteQueue& queue, std::function<void()> before_batch)
    : db_(std::move(db)),
      path_(std::move(path)),
      queue_(queue),
      before_batch_(std::move(before_batch)),
      begin_(db_.get(), "BEGIN IMMEDIATE"),
      commit_(db_.get(), "COMMIT"),
      rollback_(db_.get(), "ROLLBACK"),
      upsert_session_(db_.get(), UpsertSql(kSessionsTable)),
      remove_session_(db_.get(), "DELETE FROM sessions WHERE id = ?"),
      upsert_trial_(db_.get(), UpsertSql(kTrialsTable)),
      // submit_seq: one past the highest, so the replay order is the submission order across restarts.
      save_score_sheet_(
          db_.get(),
          "INSERT INTO score_sheets (session_id, expert, scene, indicators, submitted_unix_ms, submit_seq) "
          "VALUES (?, ?, ?, ?, ?, (SELECT COALESCE(MAX(submit_seq), 0) + 1 FROM score_sheets)) "
          "ON CONFLICT (session_id, expert) DO UPDATE SET scene = excluded.scene, "
          "indicators = excluded.indicators, submitted_unix_ms = excluded.submitted_unix_ms, "
          "submit_seq = excluded.submit_seq"),
      note_roster_(db_.get(),
                   "INSERT INTO class_roster (class_name, session_id, trainee, first_seen_unix_ms, last_seen_unix_ms) "
                   "VALUES (?, ?, ?, ?, ?) ON CONFLICT (class_name, session_id, trainee) DO UPDATE SET "
                   "first_seen_unix_ms = MIN(first_seen_unix_ms, excluded.first_seen_unix_ms), "
                   "last_seen_unix_ms = MAX(last_seen_unix_ms, excluded.last_seen_unix_ms)"),
      upsert_recording_(db_.get(), UpsertSql(kRecordingsTable)),
      mark_recording_deleted_(db_.get(), "UPDATE recordings SET status = 'deleted' WHERE path = ?"),
      thread_([this] { Run(); }) {}

StoreWriter::~StoreWriter() {
  queue_.Stop();
  thread_.join();
}

void StoreWriter::Run() {
  common::NameThisThread("hapsim-database");
  common::LowerThisThreadPriority();  // a server's ticks come first
  std::vector<StoreWrite> batch;
  std::uint64_t last_seq = 0;
  while (queue_.Take(&batch, &last_seq)) {
    if (before_batch_) before_batch_();
    Commit(batch);
    queue_.Done(last_seq);
  }
}

void StoreWriter::Error(const std::string& what) {
  const std::uint64_t n = errors_.fetch_add(1, std::memory_order_relaxed) + 1;
  if (WorthLogging(n)) {
    spdlog::error("results database '{}': {}: {} ({} write errors so far)", path_, what, sqlite3_errmsg(db_.get()), n);
  }
}

bool StoreWriter::Step(Statement& s, const char* what) {
  const int rc = s.Step();
  if (rc != SQLITE_DONE && rc != SQLITE_ROW) Error(what);  // before Reset, which would clear the message
  s.Reset();
  return rc == SQLITE_DONE || rc == SQLITE_ROW;
}

void StoreWriter::Commit(const std::vector<StoreWrite>& batch) {
  if (!Step(begin_, "cannot start a transaction; the batch is lost")) return;
  for (const StoreWrite& write : batch) {
    Apply(write);                             // one failing row does not sink the others...
    if (sqlite3_get_autocommit(db_.get())) {  // ...but one that made sqlite roll back (disk full, I/O) does
      Error("the transaction was rolled back; the batch is lost");
      return;
    }
  }
  if (Step(commit_, "cannot commit; the batch is lost")) {
    committed_.fetch_add(batch.size(), std::memory_order_relaxed);
    return;
  }
  if (!sqlite3_get_autocommit(db_.get())) Step(rollback_, "cannot roll back");
}

namespace {
template <class... F>
struct Overloaded : F... {
  using F::operator()...;
};
template <class... F>
Overloaded(F...) -> Overloaded<F...>;
}  // namespace

bool StoreWriter::Apply(const StoreWrite& write) {
  return std::visit(Overloaded{
                        [&](const StoredSession& row) {
                          BindSession(upsert_session_, row);
                          return Step(upsert_session_, "cannot save a session");
                        },
                        [&](const RemoveSessionWrite& w) {
                          Binder(remove_session_).Text(w.id);
                          return Step(remove_session_, "cannot remove a session");
                        },
                        [&](const StoredTrial& row) {
                          BindTrial(upsert_trial_, row);
                          return Step(upsert_trial_, "cannot save a trial");
                        },
                        [&](const StoredScoreSheet& row) {
                          Binder(save_score_sheet_)
                              .Text(row.session_id)
                              .Text(row.expert)
                              .Text(row.scene)
                              .Text(store_codec::EncodeDoubles(row.indicators))
                              .Int(row.submitted_unix_ms);
                          return Step(save_score_sheet_, "cannot save a score sheet");
                        },
                        [&](const NoteRosterWrite& w) {
                          const StoredRosterEntry& e = w.entry;
                          Binder(note_roster_)
                              .Text(e.class_name)
                              .Text(e.session_id)
                              .Text(e.trainee)
                              .Int(e.first_seen_unix_ms)
                              .Int(e.last_seen_unix_ms);
                          return Step(note_roster_, "cannot note a roster entry");
                        },
                        [&](const StoredRecording& row) {
                          BindRecording(upsert_recording_, row);
                          return Step(upsert_recording_, "cannot save a recording");
                        },
                        [&](const MarkRecordingDeletedWrite& w) {
                          Binder(mark_recording_deleted_).Text(w.path);
                          return Step(mark_recording_deleted_, "cannot mark a recording deleted");
                        },
                    },
                    write);
}

}  // namespace hapsim::service::store_internal
