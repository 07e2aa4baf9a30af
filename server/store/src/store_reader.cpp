#include "store_reader.h"

#include <stdexcept>

#include "hapsim/store/text_codecs.h"
#include "row_codec.h"

namespace hapsim::service::store_internal {

void StoreReader::Query(const std::string& sql, const char* what, const std::function<void(Statement&)>& bind,
                        const std::function<void(const Statement&)>& row) const {
  std::lock_guard lock(mutex_);
  std::string detail;
  try {
    Statement s(db_.get(), sql);
    if (bind) bind(s);
    for (;;) {
      const int rc = s.Step();
      if (rc == SQLITE_DONE) return;
      if (rc != SQLITE_ROW) break;
      row(s);
    }
    detail = sqlite3_errmsg(db_.get());
  } catch (const std::invalid_argument& e) {  // a list column's text did not parse
    detail = std::string("malformed row: ") + e.what();
  } catch (const std::runtime_error&) {  // prepare failed
    detail = sqlite3_errmsg(db_.get());
  }
  throw std::runtime_error(StoreErrorText(path_, std::string("cannot read ") + what, detail));
}

std::vector<StoredSession> StoreReader::Sessions() const {
  std::vector<StoredSession> out;
  Query(SelectSql(kSessionsTable, "ORDER BY created_unix_ms, id"), "sessions", {},
        [&](const Statement& s) { out.push_back(ReadSession(s)); });
  return out;
}

std::vector<StoredTrial> StoreReader::Trials(const SessionFilter& include) const {
  std::vector<StoredTrial> out;
  Query(SelectSql(kTrialsTable, "ORDER BY session_id, run_id, trial"), "trials", {}, [&](const Statement& s) {
    StoredTrial row = ReadTrial(s);
    if (!include || include(row.record.session_id)) out.push_back(std::move(row));
  });
  return out;
}

std::vector<StoredScoreSheet> StoreReader::ScoreSheets() const {
  std::vector<StoredScoreSheet> out;
  Query("SELECT session_id, scene, expert, indicators, submitted_unix_ms FROM score_sheets ORDER BY submit_seq",
        "score sheets", {}, [&](const Statement& s) {
          Cursor c(s);
          StoredScoreSheet row;
          row.session_id = c.Text();
          row.scene = c.Text();
          row.expert = c.Text();
          row.indicators = store_codec::DecodeDoubles(c.Text());
          row.submitted_unix_ms = c.Int();
          out.push_back(std::move(row));
        });
  return out;
}

std::vector<StoredRosterEntry> StoreReader::Roster() const {
  std::vector<StoredRosterEntry> out;
  Query(
      "SELECT class_name, session_id, trainee, first_seen_unix_ms, last_seen_unix_ms FROM class_roster "
      "ORDER BY class_name, session_id, trainee",
      "the roster", {}, [&](const Statement& s) {
        Cursor c(s);
        StoredRosterEntry row;
        row.class_name = c.Text();
        row.session_id = c.Text();
        row.trainee = c.Text();
        row.first_seen_unix_ms = c.Int();
        row.last_seen_unix_ms = c.Int();
        out.push_back(std::move(row));
      });
  return out;
}

std::vector<StoredRecording> StoreReader::Recordings(const SessionFilter& include) const {
  std::vector<StoredRecording> out;
  Query(SelectSql(kRecordingsTable, "ORDER BY session_id, run_id, trial, path"), "recordings", {},
        [&](const Statement& s) {
          StoredRecording row = ReadRecording(s);
          if (!include || include(row.session_id)) out.push_back(std::move(row));
        });
  return out;
}

std::vector<StoredRecording> StoreReader::RecordingsOlderThan(std::int64_t unix_ms) const {
  std::vector<StoredRecording> out;
  Query(
      SelectSql(kRecordingsTable,
                "WHERE ended_unix_ms IS NOT NULL AND ended_unix_ms < ? AND status <> 'deleted' "
                "ORDER BY ended_unix_ms, path"),
      "recordings", [&](Statement& s) { Binder(s).Int(unix_ms); },
      [&](const Statement& s) { out.push_back(ReadRecording(s)); });
  return out;
}

}  // namespace hapsim::service::store_internal
