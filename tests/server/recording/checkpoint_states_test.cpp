// Seeking in a replay: a re-run keeps states at checkpoints it reached with
// the recorded hash (at most one per stretch of the trial), and a later
// seek restores the nearest one and re-runs only from there, to exactly the
// state a re-run from the trial's start reaches.
#include "hapsim/recording/checkpoint_states.h"

#include <gtest/gtest.h>

#include "hapsim/recording/recording_reader.h"
#include "hapsim/recording/replay.h"
#include "server/recording/recording_test_support.h"

namespace hapsim::service {
namespace {

// 3000 ticks of the scripted press on tissue_block, a checkpoint every 250.
std::vector<std::uint8_t> RecordPress(const testing::ScratchDir& dir) {
  RecordingOptions options;
  options.directory = dir.path.string();
  options.queue_ticks = 3000 + 16;
  options.checkpoint_every_ticks = 250;
  RecordingService service(options);
  auto scene = core::MakeScene({"tissue_block", {}});
  {
    auto recorder = service.Attach(testing::TestSession());
    testing::RunScript(*scene, *recorder, 0, 3000);
  }
  service.Flush();
  service.Flush();
  service.Stop();
  return ReadRecordingBytes(testing::FilesUnder(dir.path).at(0).string());
}

// Re-runs up to (and including) `last_tick`, keeping states in `kept`.
ReplayResult RunTo(std::span<const std::uint8_t> bytes, std::uint64_t last_tick, CheckpointStates* kept) {
  ReplayOptions options;
  options.until_tick = last_tick;
  if (const auto nearest = kept->Nearest(last_tick + 1)) options.from = {nearest->scene, nearest->next_tick};
  options.after_matched_checkpoint = [kept](const RecordedCheckpoint& c, const core::Scene& at) {
    kept->Offer(c.tick + 1, at);
  };
  return Replay(bytes, options);
}

TEST(CheckpointStates, ASeekReRunsOnlyFromTheNearestKeptStateToTheStateOfAFullReRun) {
  testing::ScratchDir dir("seek");
  const auto bytes = RecordPress(dir);
  const std::uint64_t first = ReadRecordingHeader(bytes).first_tick;
  ReplayOptions full;
  full.until_tick = first + 2699;
  const ReplayResult reference = Replay(bytes, full);
  ASSERT_TRUE(reference.ok());
  ASSERT_EQ(reference.ticks_run, 2700u);

  CheckpointStates kept(first, 1000);
  const ReplayResult forward = RunTo(bytes, first + 2899, &kept);  // the first seek: from the start
  ASSERT_TRUE(forward.ok());
  EXPECT_EQ(forward.ticks_run, 2900u);
  // Checkpoints after ticks 249, 499, ...: the first of each 1000-tick stretch is kept.
  EXPECT_EQ(kept.size(), 3u);
  ASSERT_TRUE(kept.Nearest(first + 2700));
  EXPECT_EQ(kept.Nearest(first + 2700)->next_tick, first + 2000);
  EXPECT_EQ(kept.Nearest(first + 999)->next_tick, first + 250);
  EXPECT_FALSE(kept.Nearest(first + 249));

  const ReplayResult back = RunTo(bytes, first + 2699, &kept);  // seeking back: from the state kept at 2000
  ASSERT_TRUE(back.ok());
  EXPECT_EQ(back.ticks_run, 700u);
  EXPECT_EQ(back.checkpoints_matched, 2u);  // after ticks 2249 and 2499
  EXPECT_EQ(back.scene->StateHash(), reference.scene->StateHash());
  EXPECT_EQ(back.scene->Vertices_m(), reference.scene->Vertices_m());
  EXPECT_EQ(kept.size(), 3u);  // nothing new: those stretches already hold a state
  // The kept state itself is untouched by the seek that started from it.
  const ReplayResult again = RunTo(bytes, first + 2699, &kept);
  EXPECT_EQ(again.scene->StateHash(), reference.scene->StateHash());
}

TEST(CheckpointStates, ATrialKeepsAtMostItsBoundWhateverItsSeeks) {
  // A 10-minute trial checkpointed every second, every checkpoint offered.
  const std::uint64_t trial_ticks = 600000;
  const std::uint64_t spacing = CheckpointStates::SpacingFor(trial_ticks, 24, 1);
  EXPECT_EQ(spacing, 25000u);
  CheckpointStates kept(5, spacing);
  auto scene = core::MakeScene({"tissue_block", {}});
  for (std::uint64_t t = 5 + 999; t < 5 + trial_ticks; t += 1000) kept.Offer(t + 1, *scene);
  EXPECT_EQ(kept.size(), 25u);  // 24 stretches, and the state after the trial's last tick
  // A short trial keeps no closer than the minimum spacing.
  EXPECT_EQ(CheckpointStates::SpacingFor(3000, 24, 1000), 1000u);
}

}  // namespace
}  // namespace hapsim::service
