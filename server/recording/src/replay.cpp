#include "hapsim/recording/replay.h"

#include <chrono>

namespace hapsim::service {

ReplayResult Replay(std::span<const std::uint8_t> recording, const ReplayOptions& options) {
  const auto start = std::chrono::steady_clock::now();
  ReplayResult r;
  const RecordingHeader header = ReadRecordingHeader(recording);
  const std::uint64_t from_tick = options.from.scene ? options.from.next_tick : 0;
  r.scene = core::MakeScene({header.scene, header.params});
  if (options.from.scene) r.scene->RestoreState(*options.from.scene);
  const double period_s = header.tick_period_s;
  bool stopped = false;
  RecordingVisitor visitor;
  visitor.ticks = [&](std::span<const TickInput> ticks) {
    for (const TickInput& in : ticks) {
      if (in.tick < from_tick) continue;
      if (stopped || in.tick > options.until_tick) {
        stopped = true;
        return;
      }
      StepScene(*r.scene, in, period_s);
      ++r.ticks_run;
      r.last_input = in;
      if (options.after_tick) options.after_tick(in, *r.scene);
    }
  };
  visitor.checkpoint = [&](const RecordedCheckpoint& c) {
    if (stopped || !r.last_input || r.last_input->tick != c.tick) return;  // past until_tick
    const std::uint64_t replayed = r.scene->StateHash();
    if (replayed == c.state_hash) {
      ++r.checkpoints_matched;
      if (options.after_matched_checkpoint) options.after_matched_checkpoint(c, *r.scene);
    } else {
      r.mismatch = HashMismatch{c.tick, c.state_hash, replayed};
      stopped = true;
    }
  };
  r.summary = ReadRecording(recording, visitor);
  r.elapsed_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return r;
}

}  // namespace hapsim::service
