// Every table survives closing the store and opening the file again, with
// its values exact (doubles bit for bit, NaN as NULL and back).
#include <gtest/gtest.h>

#include "hapsim/classroom/score_book.h"
#include "hapsim/store/results_store.h"
#include "store_test_util.h"

namespace hapsim::service {
namespace {

using store_test::kNaN;
using store_test::SampleRecording;
using store_test::SampleTrial;
using store_test::TempDir;

TEST(ResultsStore, SessionsSurviveReopening) {
  TempDir dir;
  const std::string file = dir.File("results.db");
  StoredSession a{"t1",
                  "acupuncture",
                  {{"stiffness_N_per_m", 0.1}, {"third", 1.0 / 3.0}, {"odd;name=x%", -2e-310}},
                  "alice",
                  "acu-101",
                  "run-a",
                  1700000000001,
                  "/rec/t1/run-a-t0.hrec"};
  StoredSession b{"t2", "cutting", {}, "", "", "run-b", 1700000000002, ""};
  {
    auto store = ResultsStore::Open(file);
    store->UpsertSession(a);
    store->UpsertSession(b);
  }  // closing commits what is queued
  auto store = ResultsStore::Open(file);
  const auto sessions = store->Sessions();
  ASSERT_EQ(sessions.size(), 2u);
  EXPECT_EQ(sessions[0].id, "t1");
  EXPECT_EQ(sessions[0].scene, a.scene);
  EXPECT_EQ(sessions[0].params, a.params);  // exact doubles, the odd name intact
  EXPECT_EQ(sessions[0].owner, a.owner);
  EXPECT_EQ(sessions[0].class_name, a.class_name);
  EXPECT_EQ(sessions[0].run_id, a.run_id);
  EXPECT_EQ(sessions[0].created_unix_ms, a.created_unix_ms);
  EXPECT_EQ(sessions[0].recording_path, a.recording_path);
  EXPECT_EQ(sessions[1].id, "t2");
  EXPECT_TRUE(sessions[1].params.empty());
  EXPECT_EQ(sessions[1].recording_path, "");
}

TEST(ResultsStore, ARemovedSessionIsNotBroughtBack) {
  TempDir dir;
  const std::string file = dir.File("results.db");
  {
    auto store = ResultsStore::Open(file);
    store->UpsertSession({"t1", "acupuncture", {}, "alice", "c", "r", 1, ""});
    store->UpsertSession({"t2", "acupuncture", {}, "bob", "c", "r", 2, ""});
    store->RemoveSession("t1");
  }
  const auto sessions = ResultsStore::Open(file)->Sessions();
  ASSERT_EQ(sessions.size(), 1u);
  EXPECT_EQ(sessions[0].id, "t2");
}

TEST(ResultsStore, TrialsSurviveReopening) {
  TempDir dir;
  const std::string file = dir.File("results.db");
  StoredTrial touched = SampleTrial("t1", 0);
  touched.record.stats.first_contact_sim_s = 0.25;
  touched.record.targets.line_m = {-0.01, 0.0, 0.01, 1.0 / 3.0};
  touched.record.end = "reset";
  StoredTrial untouched = SampleTrial("t1", 1);  // NaN first contact, no line
  untouched.record.targets.depth_m = kNaN;
  untouched.record.layer_names = {};
  {
    auto store = ResultsStore::Open(file);
    store->UpsertTrial(untouched);
    store->UpsertTrial(touched);
  }
  auto store = ResultsStore::Open(file);
  const auto trials = store->Trials();
  ASSERT_EQ(trials.size(), 2u);
  store_test::ExpectSameTrial(trials[0], touched);
  store_test::ExpectSameTrial(trials[1], untouched);
  // The CSV export gives the same text from the stored records as from the live ones.
  EXPECT_EQ(FormatTrialsCsv({trials[0].record, trials[1].record}), FormatTrialsCsv({touched.record, untouched.record}));
}

TEST(ResultsStore, ScoreSheetsComeBackInSubmissionOrderAndReplayToTheSameScores) {
  TempDir dir;
  const std::string file = dir.File("results.db");
  ScoreBook live;
  const auto submit = [&](ResultsStore& store, const std::string& session, const std::string& scene,
                          const std::string& expert, const std::vector<double>& x) {
    live.Submit(session, scene, expert, x);
    store.SaveScoreSheet(session, scene, expert, x);
  };
  {
    auto store = ResultsStore::Open(file);
    submit(*store, "t1", "acupuncture", "dr-li", {0.1, 1.0 / 3.0, 5, 6, 7, 8, 9.99});
    submit(*store, "t1", "acupuncture", "dr-wu", {1, 2, 3, 4, 5, 6, 7});
    submit(*store, "t2", "cutting", "dr-li", {7, 7, 7, 7, 7, 7, 7});
  }
  {
    auto store = ResultsStore::Open(file);  // a restart: the next submissions go after the stored ones
    submit(*store, "t1", "acupuncture", "dr-li", {9, 9, 9, 9, 9, 9, 2.0 / 3.0});  // replaces the first sheet
    submit(*store, "t3", "vessel", "dr-wu", {1, 2, 3, 4, 5, 6, 7, 8, 9});
  }
  const auto sheets = ResultsStore::Open(file)->ScoreSheets();
  ASSERT_EQ(sheets.size(), 4u);
  EXPECT_EQ(sheets[0].session_id + "/" + sheets[0].expert, "t1/dr-wu");
  EXPECT_EQ(sheets[1].session_id + "/" + sheets[1].expert, "t2/dr-li");
  EXPECT_EQ(sheets[2].session_id + "/" + sheets[2].expert, "t1/dr-li");
  EXPECT_EQ(sheets[2].indicators, (std::vector<double>{9, 9, 9, 9, 9, 9, 2.0 / 3.0}));
  EXPECT_EQ(sheets[3].scene, "vessel");
  EXPECT_GT(sheets[0].submitted_unix_ms, 1600000000000);
  ScoreBook replayed;
  for (const auto& s : sheets) replayed.Submit(s.session_id, s.scene, s.expert, s.indicators);
  const ScoreReport want = live.Report("");
  const ScoreReport got = replayed.Report("");
  ASSERT_EQ(got.sessions.size(), want.sessions.size());
  for (std::size_t i = 0; i < want.sessions.size(); ++i) {
    EXPECT_EQ(got.sessions[i].session_id, want.sessions[i].session_id);
    EXPECT_EQ(got.sessions[i].experts, want.sessions[i].experts);
    EXPECT_EQ(got.sessions[i].comprehensive_score, want.sessions[i].comprehensive_score);  // exactly
  }
  EXPECT_EQ(got.class_mean_score, want.class_mean_score);
}

TEST(ResultsStore, TheRosterKeepsTheFirstAndLastSighting) {
  TempDir dir;
  const std::string file = dir.File("results.db");
  {
    auto store = ResultsStore::Open(file);
    store->NoteRoster("acu-101", "t1", "alice", 2000);
    store->NoteRoster("acu-101", "t1", "alice", 5000);
    store->NoteRoster("acu-101", "t1", "alice", 1000);  // out of order: still widens the span
    store->NoteRoster("acu-101", "t2", "bob", 3000);
  }
  const auto roster = ResultsStore::Open(file)->Roster();
  ASSERT_EQ(roster.size(), 2u);
  EXPECT_EQ(roster[0].trainee, "alice");
  EXPECT_EQ(roster[0].first_seen_unix_ms, 1000);
  EXPECT_EQ(roster[0].last_seen_unix_ms, 5000);
  EXPECT_EQ(roster[1].session_id, "t2");
  EXPECT_EQ(roster[1].first_seen_unix_ms, 3000);
  EXPECT_EQ(roster[1].last_seen_unix_ms, 3000);
}

TEST(ResultsStore, RecordingsSurviveReopeningWithAnOpenOneEndingInNull) {
  TempDir dir;
  const std::string file = dir.File("results.db");
  StoredRecording open = SampleRecording("t1", 1, 5000);
  StoredRecording closed = SampleRecording("t1", 0, 1000);
  closed.ended_unix_ms = 4000;
  closed.status = "closed";
  closed.bytes = (1ull << 40) + 3;
  {
    auto store = ResultsStore::Open(file);
    store->UpsertRecording(open);
    store->UpsertRecording(closed);
  }
  const auto recordings = ResultsStore::Open(file)->Recordings();
  ASSERT_EQ(recordings.size(), 2u);
  EXPECT_EQ(recordings[0].path, closed.path);
  EXPECT_EQ(recordings[0].ended_unix_ms, std::optional<std::int64_t>(4000));
  EXPECT_EQ(recordings[0].status, "closed");
  EXPECT_EQ(recordings[0].bytes, closed.bytes);
  EXPECT_EQ(recordings[0].ticks, closed.ticks);
  EXPECT_EQ(recordings[0].trainee, "bob");
  EXPECT_EQ(recordings[0].class_name, "cut-201");
  EXPECT_EQ(recordings[0].scene, "cutting");
  EXPECT_EQ(recordings[0].run_id, "run-1");
  EXPECT_EQ(recordings[0].started_unix_ms, 1000);
  EXPECT_EQ(recordings[1].path, open.path);
  EXPECT_EQ(recordings[1].trial, 1u);
  EXPECT_FALSE(recordings[1].ended_unix_ms.has_value());
  EXPECT_EQ(recordings[1].status, "open");
}

TEST(ResultsStore, RetentionListsOnlyEndedUndeletedRecordingsOlderThanTheCutoff) {
  TempDir dir;
  auto store = ResultsStore::Open(dir.File("results.db"));
  for (std::uint64_t i = 0; i < 4; ++i) {
    StoredRecording r = SampleRecording("t1", i, 1000 * static_cast<std::int64_t>(i));
    r.ended_unix_ms = 1000 * static_cast<std::int64_t>(i) + 500;  // 500, 1500, 2500, 3500
    r.status = "closed";
    store->UpsertRecording(r);
  }
  store->UpsertRecording(SampleRecording("t2", 0, 0));  // still open: never a candidate
  store->MarkRecordingDeleted(SampleRecording("t1", 0, 0).path);
  store->Flush();
  const auto old = store->RecordingsOlderThan(3000);
  ASSERT_EQ(old.size(), 2u);
  EXPECT_EQ(old[0].trial, 1u);  // oldest first
  EXPECT_EQ(old[1].trial, 2u);
  const auto all = store->Recordings();
  ASSERT_EQ(all.size(), 5u);
  EXPECT_EQ(all[0].status, "deleted");  // deleted ones stay listed, marked
}

TEST(ResultsStore, AStoreWithFsyncOnEveryCommitRoundTripsToo) {
  TempDir dir;
  const std::string file = dir.File("results.db");
  StoreOptions options;
  options.fsync_every_commit = true;
  {
    auto store = ResultsStore::Open(file, options);
    store->UpsertTrial(SampleTrial("t1", 0));
  }
  const auto trials = ResultsStore::Open(file)->Trials();
  ASSERT_EQ(trials.size(), 1u);
  store_test::ExpectSameTrial(trials[0], SampleTrial("t1", 0));
}

}  // namespace
}  // namespace hapsim::service
