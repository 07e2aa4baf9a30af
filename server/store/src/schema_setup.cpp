#include "schema_setup.h"

#include <spdlog/spdlog.h>

#include <cstdio>
#include <stdexcept>

#include "sqlite_handle.h"

namespace hapsim::service::store_internal {
namespace {

// A one-value query (a pragma or a count); throws naming what it was for.
std::int64_t QueryInt(sqlite3* db, const std::string& path, const char* sql, const char* what) {
  std::string detail;
  try {
    Statement s(db, sql);
    const int rc = s.Step();
    if (rc == SQLITE_ROW) return sqlite3_column_int64(s.get(), 0);
    if (rc == SQLITE_DONE) return 0;
    detail = sqlite3_errmsg(db);
  } catch (const std::runtime_error&) {  // prepare failed: the connection holds why
    detail = sqlite3_errmsg(db);
  }
  throw std::runtime_error(StoreErrorText(path, what, detail));
}

std::string QueryText(sqlite3* db, const std::string& path, const char* sql, const char* what) {
  std::string detail;
  try {
    Statement s(db, sql);
    if (s.Step() == SQLITE_ROW) return Cursor(s).Text();
    detail = sqlite3_errmsg(db);
  } catch (const std::runtime_error&) {
    detail = sqlite3_errmsg(db);
  }
  throw std::runtime_error(StoreErrorText(path, what, detail));
}

void Exec(sqlite3* db, const std::string& path, const std::string& sql, const std::string& what) {
  if (ExecSql(db, sql) != SQLITE_OK) throw std::runtime_error(StoreErrorText(path, what, sqlite3_errmsg(db)));
}

// Refuses anything but a hapsim results database or an empty file.
void CheckIdentity(sqlite3* db, const std::string& path, std::int64_t version) {
  // The first read of the header: a file that is not SQLite fails here ("file is not a database").
  const std::int64_t app_id = QueryInt(db, path, "PRAGMA application_id", "cannot read it");
  if (app_id == kStoreApplicationId) return;
  const std::int64_t objects = QueryInt(db, path, "SELECT count(*) FROM sqlite_schema", "cannot read it");
  if (app_id == 0 && objects == 0 && version == 0) return;  // empty: becomes one at the first migration
  char detail[96];
  std::snprintf(detail, sizeof detail, "application_id 0x%08llx, %lld schema objects",
                static_cast<unsigned long long>(app_id), static_cast<long long>(objects));
  throw std::runtime_error(
      StoreErrorText(path, "is not a hapsim results database (another program's SQLite file?)", detail));
}

void CheckSteps(const std::vector<SchemaStep>& steps) {
  for (std::size_t i = 0; i < steps.size(); ++i) {
    if (steps[i].to_version != static_cast<int>(i) + 1) {
      throw std::logic_error("schema steps must go 1, 2, 3, ... (step " + std::to_string(i) + " goes to " +
                             std::to_string(steps[i].to_version) + ")");
    }
  }
}

// One step in one transaction: a crash or an error leaves the previous version.
int ApplyStep(sqlite3* db, const std::string& path, const SchemaStep& step) {
  const std::string to = std::to_string(step.to_version);
  Exec(db, path, "BEGIN IMMEDIATE", "cannot start migrating to schema version " + to);
  // Read again under the write lock: another process may have migrated meanwhile.
  const std::int64_t now = QueryInt(db, path, "PRAGMA user_version", "cannot read the schema version");
  if (now >= step.to_version) {
    Exec(db, path, "COMMIT", "cannot end a migration");
    return static_cast<int>(now);
  }
  const std::string sql = step.sql + ";\nPRAGMA application_id = " + std::to_string(kStoreApplicationId) +
                          ";\nPRAGMA user_version = " + to + ";";
  if (ExecSql(db, sql) != SQLITE_OK || ExecSql(db, "COMMIT") != SQLITE_OK) {
    const std::string message = sqlite3_errmsg(db);
    if (!sqlite3_get_autocommit(db)) ExecSql(db, "ROLLBACK");
    throw std::runtime_error(StoreErrorText(path, "cannot migrate to schema version " + to, message));
  }
  spdlog::info("results database '{}': schema migrated to version {}", path, step.to_version);
  return step.to_version;
}

}  // namespace

int SetUpDatabase(sqlite3* db, const std::string& path, const std::vector<SchemaStep>& steps, bool fsync_every_commit) {
  CheckSteps(steps);
  // user_version first: on a non-SQLite file this is the read that fails.
  int version = static_cast<int>(QueryInt(db, path, "PRAGMA user_version", "cannot read it"));
  CheckIdentity(db, path, version);
  const int newest = steps.empty() ? 0 : steps.back().to_version;
  if (version > newest) {
    throw std::runtime_error(StoreErrorText(
        path, "schema version " + std::to_string(version) + " is newer than this build's " + std::to_string(newest),
        "written by a newer hapsim-server; use that, or another file"));
  }
  const std::string mode = QueryText(db, path, "PRAGMA journal_mode=WAL", "cannot set WAL mode");
  if (mode != "wal") {  // e.g. a file system without shared memory: still correct, readers wait for the writer
    spdlog::warn("results database '{}': journal mode is '{}', not WAL", path, mode);
  }
  Exec(db, path, fsync_every_commit ? "PRAGMA synchronous=FULL" : "PRAGMA synchronous=NORMAL",
       "cannot set synchronous");
  Exec(db, path, "PRAGMA foreign_keys=ON", "cannot enable foreign keys");
  for (const SchemaStep& step : steps) {
    if (step.to_version > version) version = ApplyStep(db, path, step);
  }
  return version;
}

}  // namespace hapsim::service::store_internal
