// Upserts update rows in place, filters select by session, and every string
// is a bound parameter: quotes, semicolons and SQL in names are just text.
#include <gtest/gtest.h>

#include "hapsim/store/results_store.h"
#include "store_test_util.h"

namespace hapsim::service {
namespace {

using store_test::SampleRecording;
using store_test::SampleTrial;
using store_test::TempDir;

TEST(ResultsStore, ARunningTrialIsUpdatedInPlaceThenFinalised) {
  TempDir dir;
  auto store = ResultsStore::Open(dir.File("results.db"));
  StoredTrial t = SampleTrial("t1", 0);
  for (std::uint64_t ticks = 100; ticks <= 500; ticks += 100) {  // the frame pump's passes
    t.record.stats.ticks = ticks;
    t.updated_unix_ms += 16;
    store->UpsertTrial(t);
    store->Flush();
    const auto trials = store->Trials();
    ASSERT_EQ(trials.size(), 1u);  // one row, updated
    EXPECT_EQ(trials[0].record.stats.ticks, ticks);
    EXPECT_EQ(trials[0].record.end, "running");
  }
  t.record.end = "reset";
  t.record.stats.first_contact_sim_s = 0.5;
  store->UpsertTrial(t);
  StoredTrial next = SampleTrial("t1", 1);  // the reset started the next trial
  store->UpsertTrial(next);
  store->Flush();
  const auto trials = store->Trials();
  ASSERT_EQ(trials.size(), 2u);
  store_test::ExpectSameTrial(trials[0], t);
  store_test::ExpectSameTrial(trials[1], next);
}

TEST(ResultsStore, TrialsOfTheSameNumberInAnotherRunAreSeparateRows) {
  TempDir dir;
  auto store = ResultsStore::Open(dir.File("results.db"));
  store->UpsertTrial(SampleTrial("t1", 0, "run-b"));
  store->UpsertTrial(SampleTrial("t1", 0, "run-a"));
  store->UpsertTrial(SampleTrial("t0", 3, "run-z"));
  store->Flush();
  const auto trials = store->Trials();
  ASSERT_EQ(trials.size(), 3u);  // by session, then run, then trial
  EXPECT_EQ(trials[0].record.session_id, "t0");
  EXPECT_EQ(trials[1].run_id, "run-a");
  EXPECT_EQ(trials[2].run_id, "run-b");
}

TEST(ResultsStore, TrialsAndRecordingsAreFilteredBySession) {
  TempDir dir;
  auto store = ResultsStore::Open(dir.File("results.db"));
  for (const char* session : {"t1", "t2", "t3"}) {
    store->UpsertTrial(SampleTrial(session, 0));
    store->UpsertTrial(SampleTrial(session, 1));
    store->UpsertRecording(SampleRecording(session, 0, 1000));
  }
  store->Flush();
  const auto mine = [](const std::string& id) { return id == "t2"; };
  const auto trials = store->Trials(mine);
  ASSERT_EQ(trials.size(), 2u);
  for (const auto& t : trials) EXPECT_EQ(t.record.session_id, "t2");
  const auto recordings = store->Recordings(mine);
  ASSERT_EQ(recordings.size(), 1u);
  EXPECT_EQ(recordings[0].session_id, "t2");
  EXPECT_EQ(store->Trials().size(), 6u);
  EXPECT_TRUE(store->Trials([](const std::string&) { return false; }).empty());
}

TEST(ResultsStore, ARecordingIsUpdatedInPlaceUntilItCloses) {
  TempDir dir;
  auto store = ResultsStore::Open(dir.File("results.db"));
  StoredRecording r = SampleRecording("t1", 0, 1000);
  store->UpsertRecording(r);
  r.ticks = 99999;
  r.bytes = 123456;
  r.ended_unix_ms = 9000;
  r.status = "closed";
  store->UpsertRecording(r);
  store->Flush();
  const auto recordings = store->Recordings();
  ASSERT_EQ(recordings.size(), 1u);
  EXPECT_EQ(recordings[0].ticks, 99999u);
  EXPECT_EQ(recordings[0].bytes, 123456u);
  EXPECT_EQ(recordings[0].ended_unix_ms, std::optional<std::int64_t>(9000));
  EXPECT_EQ(recordings[0].status, "closed");
}

TEST(ResultsStore, StringsWithQuotesSemicolonsAndSqlSurviveAsText) {
  TempDir dir;
  const std::string file = dir.File("results.db");
  const std::string evil = "x'); DROP TABLE trials; --\"";
  const std::string evil2 = "o'brien; DELETE FROM sessions WHERE '1'='1";
  const std::string with_nul("nul\0byte", 8);
  {
    auto store = ResultsStore::Open(file);
    StoredTrial t = SampleTrial(evil, 0);
    t.record.trainee = evil2;
    t.record.layer_names = {"a;b", "c|d", "e%7Cf", "'"};
    store->UpsertTrial(t);
    store->UpsertSession({evil, evil2, {{evil2, 1.5}}, evil2, evil, evil, 1, with_nul});
    store->SaveScoreSheet(evil, "acupuncture", evil2, {1, 2, 3, 4, 5, 6, 7});
    store->NoteRoster(evil, evil2, evil, 7);
    StoredRecording r = SampleRecording("t1", 0, 1);
    r.path = evil2;
    store->UpsertRecording(r);
    store->MarkRecordingDeleted(evil2);
    store->Flush();
    EXPECT_EQ(store->write_errors(), 0u);
  }
  auto store = ResultsStore::Open(file);
  const auto trials = store->Trials();
  ASSERT_EQ(trials.size(), 1u);
  EXPECT_EQ(trials[0].record.session_id, evil);
  EXPECT_EQ(trials[0].record.trainee, evil2);
  EXPECT_EQ(trials[0].record.layer_names, (std::vector<std::string>{"a;b", "c|d", "e%7Cf", "'"}));
  const auto sessions = store->Sessions();
  ASSERT_EQ(sessions.size(), 1u);
  EXPECT_EQ(sessions[0].id, evil);
  EXPECT_EQ(sessions[0].params.at(evil2), 1.5);
  EXPECT_EQ(sessions[0].recording_path, with_nul);
  const auto sheets = store->ScoreSheets();
  ASSERT_EQ(sheets.size(), 1u);
  EXPECT_EQ(sheets[0].expert, evil2);
  const auto roster = store->Roster();
  ASSERT_EQ(roster.size(), 1u);
  EXPECT_EQ(roster[0].class_name, evil);
  const auto recordings = store->Recordings();
  ASSERT_EQ(recordings.size(), 1u);
  EXPECT_EQ(recordings[0].path, evil2);
  EXPECT_EQ(recordings[0].status, "deleted");
}

}  // namespace
}  // namespace hapsim::service
