// Opening a file: a new one is created at the newest schema (in WAL mode),
// an older one is migrated step by step keeping its rows, and anything the
// store cannot trust is refused with a message naming the file and why.
#include <gtest/gtest.h>
#include <sqlite3.h>

#include <fstream>
#include <stdexcept>

#include "hapsim/store/results_store.h"
#include "store_test_util.h"

namespace hapsim::service {
namespace {

using store_test::SampleTrial;
using store_test::TempDir;

// A pragma's value read with a plain connection (what another program sees).
std::string SchemaPragma(const std::string& file, const std::string& pragma) {
  sqlite3* db = nullptr;
  EXPECT_EQ(sqlite3_open_v2(file.c_str(), &db, SQLITE_OPEN_READONLY, nullptr), SQLITE_OK);
  sqlite3_stmt* s = nullptr;
  std::string value;
  if (sqlite3_prepare_v2(db, ("PRAGMA " + pragma).c_str(), -1, &s, nullptr) == SQLITE_OK &&
      sqlite3_step(s) == SQLITE_ROW) {
    value = reinterpret_cast<const char*>(sqlite3_column_text(s, 0));
  }
  sqlite3_finalize(s);
  sqlite3_close(db);
  return value;
}

void RunSql(const std::string& file, const std::string& sql) {
  sqlite3* db = nullptr;
  ASSERT_EQ(sqlite3_open(file.c_str(), &db), SQLITE_OK);
  EXPECT_EQ(sqlite3_exec(db, sql.c_str(), nullptr, nullptr, nullptr), SQLITE_OK) << sqlite3_errmsg(db);
  sqlite3_close(db);
}

// The message of the runtime_error Open throws ("" if it opened).
std::string OpenError(const std::string& file, const StoreOptions& options = {}) {
  try {
    ResultsStore::Open(file, options);
  } catch (const std::runtime_error& e) {
    return e.what();
  }
  return "";
}

// This build's steps plus a version 2 (as a later build would have them).
std::vector<SchemaStep> StepsWithVersion2(const std::string& v2_sql) {
  std::vector<SchemaStep> steps = SchemaSteps();
  steps.push_back({2, v2_sql});
  return steps;
}

TEST(ResultsStoreSchema, ANewFileIsCreatedAtTheNewestVersionInWalMode) {
  TempDir dir;
  const std::string file = dir.File("results.db");
  {
    auto store = ResultsStore::Open(file);
    EXPECT_EQ(store->schema_version(), SchemaSteps().back().to_version);
    EXPECT_EQ(store->path(), file);
  }
  EXPECT_EQ(SchemaPragma(file, "user_version"), std::to_string(SchemaSteps().back().to_version));
  EXPECT_EQ(SchemaPragma(file, "application_id"), std::to_string(kStoreApplicationId));
  EXPECT_EQ(SchemaPragma(file, "journal_mode"), "wal");  // persistent in the file
}

TEST(ResultsStoreSchema, AnEmptyVersionZeroFileIsMigrated) {
  TempDir dir;
  const std::string file = dir.File("results.db");
  std::ofstream(file).close();  // zero bytes: an empty SQLite database, version 0
  auto store = ResultsStore::Open(file);
  EXPECT_EQ(store->schema_version(), 1);
  store->UpsertTrial(SampleTrial("t1", 0));
  store->Flush();
  EXPECT_EQ(store->Trials().size(), 1u);
}

TEST(ResultsStoreSchema, AnOlderFileIsMigratedKeepingItsRows) {
  TempDir dir;
  const std::string file = dir.File("results.db");
  {
    auto v1 = ResultsStore::Open(file);
    v1->UpsertTrial(SampleTrial("t1", 0));
    v1->SaveScoreSheet("t1", "acupuncture", "dr-li", {1, 2, 3, 4, 5, 6, 7});
  }
  const auto steps = StepsWithVersion2(
      "ALTER TABLE trials ADD COLUMN notes TEXT NOT NULL DEFAULT 'n/a';"
      "CREATE TABLE audit (at_unix_ms INTEGER NOT NULL, what TEXT NOT NULL);");
  StoreOptions later;
  later.schema = &steps;
  {
    auto v2 = ResultsStore::Open(file, later);
    EXPECT_EQ(v2->schema_version(), 2);
    const auto trials = v2->Trials();  // the rows and the newer code's reads both still work
    ASSERT_EQ(trials.size(), 1u);
    store_test::ExpectSameTrial(trials[0], SampleTrial("t1", 0));
    EXPECT_EQ(v2->ScoreSheets().size(), 1u);
    v2->UpsertTrial(SampleTrial("t1", 1));  // writes fill the new column's default
    v2->Flush();
    EXPECT_EQ(v2->write_errors(), 0u);
  }
  EXPECT_EQ(SchemaPragma(file, "user_version"), "2");
  EXPECT_EQ(ResultsStore::Open(file, later)->Trials().size(), 2u);  // already at 2: nothing to do
}

TEST(ResultsStoreSchema, AFailedStepLeavesTheFileAtTheLastCompletedVersion) {
  TempDir dir;
  const std::string file = dir.File("results.db");
  std::vector<SchemaStep> steps = StepsWithVersion2("CREATE TABLE extra (x INTEGER);");
  steps.push_back({3, "CREATE TABLE half_done (x INTEGER); CREATE TABLE trials (x INTEGER);"});  // trials exists
  StoreOptions options;
  options.schema = &steps;
  const std::string error = OpenError(file, options);
  EXPECT_NE(error.find(file), std::string::npos) << error;
  EXPECT_NE(error.find("cannot migrate to schema version 3"), std::string::npos) << error;
  EXPECT_NE(error.find("already exists"), std::string::npos) << error;  // sqlite's own words
  EXPECT_EQ(SchemaPragma(file, "user_version"), "2");                   // steps 1 and 2 committed, 3 rolled back whole
  std::vector<SchemaStep> two(steps.begin(), steps.begin() + 2);
  options.schema = &two;
  auto store = ResultsStore::Open(file, options);
  EXPECT_EQ(store->schema_version(), 2);
  EXPECT_EQ(SchemaPragma(file, "user_version"), "2");
}

TEST(ResultsStoreSchema, ANewerFileIsRefusedAndLeftUntouched) {
  TempDir dir;
  const std::string file = dir.File("results.db");
  const auto steps = StepsWithVersion2("CREATE TABLE extra (x INTEGER);");
  StoreOptions later;
  later.schema = &steps;
  {
    auto v2 = ResultsStore::Open(file, later);
    v2->UpsertTrial(SampleTrial("t1", 0));
  }
  const std::string error = OpenError(file);  // this build knows version 1 only
  EXPECT_NE(error.find(file), std::string::npos) << error;
  EXPECT_NE(error.find("schema version 2 is newer than this build's 1"), std::string::npos) << error;
  EXPECT_EQ(SchemaPragma(file, "user_version"), "2");
  EXPECT_EQ(ResultsStore::Open(file, later)->Trials().size(), 1u);
}

TEST(ResultsStoreSchema, AFileThatIsNotADatabaseIsRefused) {
  TempDir dir;
  const std::string file = dir.File("results.db");
  {
    std::ofstream out(file);
    for (int i = 0; i < 200; ++i) out << "session,trainee,scene,trial,end\n";  // a CSV saved under the wrong name
  }
  const std::string error = OpenError(file);
  EXPECT_NE(error.find("results database '" + file + "'"), std::string::npos) << error;
  EXPECT_NE(error.find("file is not a database"), std::string::npos) << error;
}

TEST(ResultsStoreSchema, AnotherProgramsSqliteFileIsRefusedAndLeftUntouched) {
  TempDir dir;
  const std::string file = dir.File("other.db");
  RunSql(file, "CREATE TABLE contacts (name TEXT); INSERT INTO contacts VALUES ('x');");
  const std::string error = OpenError(file);
  EXPECT_NE(error.find(file), std::string::npos) << error;
  EXPECT_NE(error.find("is not a hapsim results database"), std::string::npos) << error;
  EXPECT_EQ(SchemaPragma(file, "journal_mode"), "delete");  // not switched to WAL
  EXPECT_EQ(SchemaPragma(file, "user_version"), "0");
}

TEST(ResultsStoreSchema, AFileInAMissingDirectoryIsRefused) {
  TempDir dir;
  const std::string file = dir.File("no/such/dir/results.db");
  const std::string error = OpenError(file);
  EXPECT_NE(error.find(file), std::string::npos) << error;
  EXPECT_NE(error.find("cannot open"), std::string::npos) << error;
  EXPECT_NE(error.find("directory"), std::string::npos) << error;
}

}  // namespace
}  // namespace hapsim::service
