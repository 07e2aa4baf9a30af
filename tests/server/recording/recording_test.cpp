// The trial recording: what goes in comes back out bit for bit, a replay
// reaches every recorded state hash, and a damaged file is read up to the
// exact record that is damaged.
#include <gtest/gtest.h>

#include <cstring>
#include <fstream>

#include "core/allocation_counter.h"
#include "hapsim/recording/recording_player.h"
#include "hapsim/recording/recording_reader.h"
#include "hapsim/recording/replay.h"
#include "server/recording/recording_test_support.h"

namespace hapsim::service {
namespace {

using testing::FilesUnder;
using testing::RunScript;
using testing::ScratchDir;
using testing::ScriptedInput;
using testing::TestSession;

bool SameInput(const TickInput& a, const TickInput& b) {
  return a.tick == b.tick && a.tool.valid == b.tool.valid && a.tool.tip_W_m == b.tool.tip_W_m &&
         a.tool.orientation_W.coeffs() == b.tool.orientation_W.coeffs() &&
         a.tool.velocity_W_m_per_s == b.tool.velocity_W_m_per_s && a.tool.buttons == b.tool.buttons &&
         a.device_id == b.device_id && a.pose_seq == b.pose_seq && a.fresh_pose == b.fresh_pose &&
         a.paused == b.paused && a.reset == b.reset;
}

// Records `ticks` ticks of the script (resets and pause as given) and returns the files written.
std::vector<std::filesystem::path> RecordScript(const std::filesystem::path& dir, std::uint64_t ticks,
                                                const std::vector<std::uint64_t>& reset_at = {},
                                                std::uint64_t paused_from = 0, std::uint64_t paused_to = 0) {
  RecordingOptions options;
  options.directory = dir.string();
  options.queue_ticks = ticks + 16;
  options.checkpoint_every_ticks = 250;
  RecordingService service(options);
  auto scene = core::MakeScene({"tissue_block", {}});
  {
    auto recorder = service.Attach(TestSession());
    RunScript(*scene, *recorder, 0, ticks, reset_at, paused_from, paused_to);
  }  // the session is gone: its trial ends
  service.Flush();
  service.Flush();
  service.Stop();
  return FilesUnder(dir);
}

TEST(RecordingFormat, ATickBlockDecodesToExactlyTheInputsEncoded) {
  std::vector<TickInput> ticks;
  for (std::uint64_t t = 100; t < 100 + 777; ++t) {
    TickInput in = ScriptedInput(t);
    in.tool.orientation_W = Eigen::Quaterniond(Eigen::AngleAxisd(0.001 * t, Eigen::Vector3d(1, 2, 3).normalized()));
    in.tool.buttons = static_cast<std::uint32_t>(t % 3);
    in.paused = t % 5 == 0;
    in.reset = t == 150;
    ticks.push_back(in);
  }
  const auto payload = EncodeTickBlock(ticks);
  const auto back = DecodeTickBlock(payload, 100, static_cast<std::uint32_t>(ticks.size()));
  ASSERT_EQ(back.size(), ticks.size());
  for (std::size_t i = 0; i < ticks.size(); ++i) ASSERT_TRUE(SameInput(back[i], ticks[i])) << "tick " << i;
  // The XOR-and-byte-plane layout is what makes a 1 kHz pose stream small:
  // 97 raw bytes per tick must compress at least 2x.
  EXPECT_LT(payload.size(), ticks.size() * 97 / 2);
  std::printf("777 ticks of a moving tool: %zu bytes (%.1f per tick, %zu raw)\n", payload.size(),
              static_cast<double>(payload.size()) / 777.0, ticks.size() * 97);
}

TEST(RecordingFormat, BlocksOfNonConsecutiveTicksAreRefused) {
  std::vector<TickInput> ticks = {ScriptedInput(5), ScriptedInput(7)};
  EXPECT_THROW(EncodeTickBlock(ticks), std::invalid_argument);
}

TEST(RecordingReplay, AReplayReachesEveryRecordedStateHash) {
  ScratchDir dir("replay");
  const auto files = RecordScript(dir.path, 3000);
  ASSERT_EQ(files.size(), 1u);
  const auto bytes = ReadRecordingBytes(files[0].string());
  const ReplayResult r = Replay(bytes);
  EXPECT_TRUE(r.summary.ended);
  EXPECT_FALSE(r.summary.damage);
  EXPECT_EQ(r.ticks_run, 3000u);
  EXPECT_EQ(r.summary.checkpoints, 12u);  // every 250 ticks
  EXPECT_EQ(r.checkpoints_matched, 12u);
  EXPECT_TRUE(r.ok());
  // And the scene really was pressed: a replay of nothing would match nothing.
  EXPECT_EQ(r.summary.header.scene, "tissue_block");
  EXPECT_EQ(r.summary.header.owner, "alice");
}

TEST(RecordingReplay, AChangedInputIsCaughtAtTheNextCheckpoint) {
  ScratchDir dir("tamper");
  const auto files = RecordScript(dir.path, 1000);
  auto bytes = ReadRecordingBytes(files[0].string());
  // Rewrite the file with tick 600 pressed 1 µm deeper, checksums valid:
  // only the physics can tell.
  std::vector<std::uint8_t> out(bytes.begin(), bytes.begin() + static_cast<std::ptrdiff_t>(bytes.size()));
  std::vector<std::uint8_t> rebuilt;
  const RecordingHeader header = ReadRecordingHeader(bytes);
  rebuilt = EncodeFileHeader(header);
  RecordingVisitor v;
  v.ticks = [&](std::span<const TickInput> ticks) {
    std::vector<TickInput> copy(ticks.begin(), ticks.end());
    for (auto& in : copy) {
      if (in.tick == 600) in.tool.tip_W_m.z() -= 1e-6;
    }
    const auto rec = EncodeRecord(RecordKind::kTicks, copy.front().tick, static_cast<std::uint32_t>(copy.size()),
                                  EncodeTickBlock(copy));
    rebuilt.insert(rebuilt.end(), rec.begin(), rec.end());
  };
  v.checkpoint = [&](const RecordedCheckpoint& c) {
    const auto rec = EncodeRecord(RecordKind::kCheckpoint, c.tick, 1, EncodeCheckpoint(c.state_hash, c.sim_time_s));
    rebuilt.insert(rebuilt.end(), rec.begin(), rec.end());
  };
  ReadRecording(bytes, v);
  const ReplayResult r = Replay(rebuilt);
  ASSERT_TRUE(r.mismatch);
  EXPECT_EQ(r.mismatch->tick, 749u);  // the first checkpoint after tick 600 (every 250 ticks: 249, 499, 749)
  EXPECT_EQ(r.checkpoints_matched, 2u);
}

TEST(RecordingReplay, AResetStartsTheNextTrialInItsOwnFileAndEachReplaysAlone) {
  ScratchDir dir("reset");
  const auto files = RecordScript(dir.path, 2400, {1000}, 1500, 1700);
  ASSERT_EQ(files.size(), 2u);
  EXPECT_EQ(files[0].filename(), "run1-t0000.hrec");
  EXPECT_EQ(files[1].filename(), "run1-t0001.hrec");
  const ReplayResult first = Replay(ReadRecordingBytes(files[0].string()));
  const ReplayResult second = Replay(ReadRecordingBytes(files[1].string()));
  EXPECT_EQ(first.ticks_run, 1000u);
  EXPECT_EQ(first.checkpoints_matched, 4u);
  // The second trial starts at the reset tick, from a fresh scene: the reset
  // makes the live scene's hash a fresh scene's, so the replay matches.
  EXPECT_EQ(second.summary.header.first_tick, 1000u);
  EXPECT_EQ(second.summary.header.trial, 1u);
  EXPECT_EQ(second.ticks_run, 1400u);
  EXPECT_EQ(second.checkpoints_matched, 5u);
  EXPECT_TRUE(first.ok() && second.ok());
}

TEST(RecordingReader, ATruncatedFileIsReadUpToItsLastWholeRecordAtEveryCut) {
  ScratchDir dir("cut");
  const auto files = RecordScript(dir.path, 600);
  const auto bytes = ReadRecordingBytes(files[0].string());
  const RecordingSummary whole = ReadRecording(bytes);
  ASSERT_TRUE(whole.ended);
  const std::size_t header_bytes = EncodeFileHeader(whole.header).size();
  std::uint64_t last_valid = header_bytes;
  for (std::size_t cut = header_bytes; cut < bytes.size(); ++cut) {
    const RecordingSummary s = ReadRecording(std::span(bytes).first(cut));
    ASSERT_LE(s.valid_bytes, cut);
    ASSERT_GE(s.valid_bytes, last_valid);  // a longer prefix never reads less
    last_valid = s.valid_bytes;
    if (s.valid_bytes < cut) {
      ASSERT_TRUE(s.damage) << "cut at " << cut;
      EXPECT_EQ(s.damage->byte_offset(), s.valid_bytes);
      EXPECT_EQ(s.damage->record_index(), static_cast<std::int64_t>(s.records));
    }
    EXPECT_FALSE(s.ended);
  }
  for (std::size_t cut = 0; cut < header_bytes; ++cut) {
    EXPECT_THROW(ReadRecording(std::span(bytes).first(cut)), RecordingError);
  }
}

TEST(RecordingReader, AFlippedByteIsReportedAtTheRecordItIsIn) {
  ScratchDir dir("flip");
  const auto files = RecordScript(dir.path, 600);
  const auto bytes = ReadRecordingBytes(files[0].string());
  // Where each record starts.
  std::vector<std::uint64_t> starts;
  const std::size_t header_bytes = EncodeFileHeader(ReadRecordingHeader(bytes)).size();
  for (std::size_t at = header_bytes; at < bytes.size();) {
    starts.push_back(at);
    std::uint32_t length;
    std::memcpy(&length, bytes.data() + at + 4, 4);
    at += kRecordHeaderBytes + length;
  }
  ASSERT_GE(starts.size(), 4u);
  for (std::size_t k = 0; k < starts.size(); ++k) {
    auto damaged = bytes;
    const std::size_t end = k + 1 < starts.size() ? starts[k + 1] : bytes.size();
    damaged[(starts[k] + end) / 2] ^= 0x10;
    const RecordingSummary s = ReadRecording(damaged);
    ASSERT_TRUE(s.damage) << "record " << k;
    EXPECT_EQ(s.damage->record_index(), static_cast<std::int64_t>(k));
    EXPECT_EQ(s.damage->byte_offset(), starts[k]);
    EXPECT_EQ(s.records, k);
  }
}

TEST(RecordingReader, AFileOfAnotherKindIsRefusedWithTheReason) {
  const std::string text = "solid cube\nendsolid\n";
  const std::vector<std::uint8_t> bytes(text.begin(), text.end());
  try {
    ReadRecording(bytes);
    FAIL() << "read an STL file as a recording";
  } catch (const RecordingError& e) {
    EXPECT_NE(std::string(e.what()).find("not a hapsim trial recording"), std::string::npos) << e.what();
  }
}

TEST(RecordingService, AFullQueueLosesTicksCountedAndTheRecordingStopsAtTheGap) {
  ScratchDir dir("full");
  RecordingOptions options;
  options.directory = dir.path.string();
  options.queue_ticks = 300;
  options.checkpoint_every_ticks = 100;
  RecordingService service(options);
  auto scene = core::MakeScene({"tissue_block", {}});
  auto recorder = service.Attach(TestSession());
  RunScript(*scene, *recorder, 0, 200);
  service.Flush();                         // 200 written
  RunScript(*scene, *recorder, 200, 500);  // the writer does not run: 300 fit, 200 are lost
  EXPECT_EQ(recorder->lost_ticks(), 200u);
  service.Flush();
  RunScript(*scene, *recorder, 700, 100);  // after the gap: not written (no reset yet)
  service.Flush();
  EXPECT_EQ(service.stats().ticks_lost, 200u);
  EXPECT_EQ(service.stats().ticks_written, 500u);
  const auto files = FilesUnder(dir.path);
  ASSERT_EQ(files.size(), 1u);
  const ReplayResult r = Replay(ReadRecordingBytes(files[0].string()));
  EXPECT_EQ(r.summary.gap_at_tick, 500u);
  EXPECT_EQ(r.ticks_run, 500u);
  EXPECT_EQ(r.checkpoints_matched, 5u);
  EXPECT_TRUE(r.ok());
}

TEST(RecordingService, TheTickNeitherWaitsNorAllocatesToRecord) {
  ScratchDir dir("alloc");
  RecordingOptions options;
  options.directory = dir.path.string();
  RecordingService service(options);
  auto scene = core::MakeScene({"tissue_block", {}});
  auto recorder = service.Attach(TestSession());
  RunScript(*scene, *recorder, 0, 10);
  // The tick's part: a push into a preallocated ring and, at checkpoints, the hash.
  hapsim::test::ScopedAllocationCount counting;
  RunScript(*scene, *recorder, 10, 2000);
  EXPECT_EQ(counting.Count(), 0u);
}

}  // namespace
}  // namespace hapsim::service

namespace hapsim::service {
namespace {

// A player drives a scene the way a replay session's tick does: an input
// from Next(), the step, then OnTick to compare the state hash.
struct PlayedTicks {
  std::uint64_t stepped = 0;
};
PlayedTicks PlayInto(RecordingPlayer& player, core::Scene& scene, std::uint64_t max_ticks) {
  PlayedTicks played;
  for (std::uint64_t i = 0; i < max_ticks; ++i) {
    TickInput in;
    if (!player.Next(&in)) break;
    StepScene(scene, in, 1e-3);
    player.OnTick(TickOutcome{in, scene, scene.ForceModel().state, scene.ToolForce_W_N().norm()});
    ++played.stepped;
  }
  return played;
}

TEST(RecordingPlayer, PlayingATrialIntoAFreshSceneReachesEveryRecordedHash) {
  testing::ScratchDir dir("player");
  const auto files = RecordScript(dir.path, 2000);
  RecordingPlayer player(ReadRecordingBytes(files[0].string()), 0);
  auto scene = core::MakeScene({"tissue_block", {}});
  EXPECT_EQ(PlayInto(player, *scene, 5000).stepped, 2000u);
  const auto p = player.progress();
  EXPECT_TRUE(p.ended);
  EXPECT_EQ(p.checkpoints_matched, 8u);
  EXPECT_EQ(p.checkpoints_diverged, 0u);
}

TEST(RecordingPlayer, ASceneThatIsNotTheRecordedOneIsCaughtAtTheFirstCheckpoint) {
  testing::ScratchDir dir("player-wrong");
  const auto files = RecordScript(dir.path, 600);
  RecordingPlayer player(ReadRecordingBytes(files[0].string()), 0);
  auto scene = core::MakeScene({"tissue_block", {{"size_m", 0.031}}});  // another patch: every hash differs
  PlayInto(player, *scene, 600);
  EXPECT_EQ(player.progress().checkpoints_matched, 0u);
  EXPECT_EQ(player.progress().checkpoints_diverged, 2u);
}

TEST(RecordingPlayer, StartingLaterAndRewindingGiveTheRecordedInputsOfThoseTicks) {
  testing::ScratchDir dir("player-seek");
  const auto files = RecordScript(dir.path, 1500);
  const auto bytes = ReadRecordingBytes(files[0].string());
  std::vector<TickInput> all;
  RecordingVisitor v;
  v.ticks = [&](std::span<const TickInput> t) { all.insert(all.end(), t.begin(), t.end()); };
  ReadRecording(bytes, v);
  RecordingPlayer player(bytes, 777);
  TickInput in;
  ASSERT_TRUE(player.Next(&in));
  EXPECT_TRUE(SameInput(in, all[777]));
  for (int i = 0; i < 300; ++i) ASSERT_TRUE(player.Next(&in));
  EXPECT_TRUE(SameInput(in, all[1077]));
  player.Rewind();
  ASSERT_TRUE(player.Next(&in));
  EXPECT_TRUE(SameInput(in, all[0]));
  EXPECT_EQ(player.progress().next_tick, 1u);
  EXPECT_THROW(RecordingPlayer(bytes, 1500), std::invalid_argument);
}

TEST(RecordingPlayer, StepsAreGrantedOneAtATimeAsAskedFor) {
  testing::ScratchDir dir("player-steps");
  const auto files = RecordScript(dir.path, 100);
  RecordingPlayer player(ReadRecordingBytes(files[0].string()), 0);
  EXPECT_FALSE(player.TakeStep());
  player.RequestSteps(3);
  EXPECT_TRUE(player.TakeStep());
  EXPECT_TRUE(player.TakeStep());
  EXPECT_TRUE(player.TakeStep());
  EXPECT_FALSE(player.TakeStep());
}

TEST(RecordingPlayer, PlayingNeverAllocatesOnTheTick) {
  testing::ScratchDir dir("player-alloc");
  const auto files = RecordScript(dir.path, 3000);
  RecordingPlayer player(ReadRecordingBytes(files[0].string()), 0);
  auto scene = core::MakeScene({"tissue_block", {}});
  PlayInto(player, *scene, 10);
  hapsim::test::ScopedAllocationCount counting;
  PlayInto(player, *scene, 2990);
  player.Rewind();
  PlayInto(player, *scene, 100);
  EXPECT_EQ(counting.Count(), 0u);
}

}  // namespace
}  // namespace hapsim::service
