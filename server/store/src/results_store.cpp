#include "hapsim/store/results_store.h"

#include <spdlog/spdlog.h>

#include "schema_setup.h"
#include "sqlite_handle.h"
#include "store_reader.h"
#include "store_writer.h"
#include "write_queue.h"

namespace hapsim::service {

using store_internal::StoreWrite;

namespace {

std::int64_t StoreNowUnixMs() {
  return std::chrono::duration_cast<std::chrono::milliseconds>(std::chrono::system_clock::now().time_since_epoch())
      .count();
}

}  // namespace

struct ResultsStore::Impl {
  Impl(std::string path_in, int version, const StoreOptions& options, store_internal::DbHandle writer_db,
       store_internal::DbHandle reader_db)
      : path(std::move(path_in)),
        schema_version(version),
        queue(options.queue_capacity, options.batch_interval),
        reader(std::move(reader_db), path),
        writer(std::move(writer_db), path, queue, options.before_batch) {}

  bool Push(StoreWrite write) {
    if (queue.Push(std::move(write))) return true;
    const std::uint64_t n = queue.dropped();
    if (store_internal::WorthLogging(n)) {
      spdlog::warn("results database '{}': write queue full, a write was dropped ({} so far)", path, n);
    }
    return false;
  }

  const std::string path;
  const int schema_version;
  store_internal::WriteQueue queue;
  store_internal::StoreReader reader;
  store_internal::StoreWriter writer;  // last: its destructor drains the queue and joins first
};

std::unique_ptr<ResultsStore> ResultsStore::Open(const std::string& path, const StoreOptions& options) {
  const int busy_ms = static_cast<int>(options.busy_timeout.count());
  // The writer's connection creates and migrates the file; the reader's opens it afterwards, read-only.
  auto writer_db =
      store_internal::OpenDb(path, SQLITE_OPEN_READWRITE | SQLITE_OPEN_CREATE | SQLITE_OPEN_NOMUTEX, busy_ms);
  const int version = store_internal::SetUpDatabase(
      writer_db.get(), path, options.schema ? *options.schema : SchemaSteps(), options.fsync_every_commit);
  auto reader_db = store_internal::OpenDb(path, SQLITE_OPEN_READONLY | SQLITE_OPEN_NOMUTEX, busy_ms);
  auto impl = std::make_unique<Impl>(path, version, options, std::move(writer_db), std::move(reader_db));
  spdlog::info("results database '{}' open (schema version {}, synchronous={})", path, version,
               options.fsync_every_commit ? "FULL" : "NORMAL");
  return std::unique_ptr<ResultsStore>(new ResultsStore(std::move(impl)));
}

ResultsStore::ResultsStore(std::unique_ptr<Impl> impl) : impl_(std::move(impl)) {}
ResultsStore::~ResultsStore() = default;

const std::string& ResultsStore::path() const { return impl_->path; }
int ResultsStore::schema_version() const { return impl_->schema_version; }

bool ResultsStore::UpsertSession(const StoredSession& session) { return impl_->Push(session); }

bool ResultsStore::RemoveSession(const std::string& id) { return impl_->Push(store_internal::RemoveSessionWrite{id}); }

bool ResultsStore::UpsertTrial(const StoredTrial& trial) { return impl_->Push(trial); }

bool ResultsStore::SaveScoreSheet(const std::string& session_id, const std::string& scene, const std::string& expert,
                                  const std::vector<double>& indicators) {
  return impl_->Push(StoredScoreSheet{session_id, scene, expert, indicators, StoreNowUnixMs()});
}

bool ResultsStore::NoteRoster(const std::string& class_name, const std::string& session_id, const std::string& trainee,
                              std::int64_t now_unix_ms) {
  return impl_->Push(
      store_internal::NoteRosterWrite{StoredRosterEntry{class_name, session_id, trainee, now_unix_ms, now_unix_ms}});
}

bool ResultsStore::UpsertRecording(const StoredRecording& recording) { return impl_->Push(recording); }

bool ResultsStore::MarkRecordingDeleted(const std::string& path) {
  return impl_->Push(store_internal::MarkRecordingDeletedWrite{path});
}

void ResultsStore::Flush() { impl_->queue.Flush(); }

std::vector<StoredSession> ResultsStore::Sessions() const { return impl_->reader.Sessions(); }

std::vector<StoredTrial> ResultsStore::Trials(const std::function<bool(const std::string&)>& include) const {
  return impl_->reader.Trials(include);
}

std::vector<StoredScoreSheet> ResultsStore::ScoreSheets() const { return impl_->reader.ScoreSheets(); }

std::vector<StoredRosterEntry> ResultsStore::Roster() const { return impl_->reader.Roster(); }

std::vector<StoredRecording> ResultsStore::Recordings(const std::function<bool(const std::string&)>& include) const {
  return impl_->reader.Recordings(include);
}

std::vector<StoredRecording> ResultsStore::RecordingsOlderThan(std::int64_t unix_ms) const {
  return impl_->reader.RecordingsOlderThan(unix_ms);
}

std::uint64_t ResultsStore::dropped_writes() const { return impl_->queue.dropped(); }
std::uint64_t ResultsStore::write_errors() const { return impl_->writer.errors(); }
std::uint64_t ResultsStore::committed_writes() const { return impl_->writer.committed(); }

}  // namespace hapsim::service
