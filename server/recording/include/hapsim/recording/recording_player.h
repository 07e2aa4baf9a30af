// A trial recording played into a live session that viewers watch like any
// other: the session's TickInputSource (the recorded inputs, in order) and
// its TickListener (the scene's state hash compared with the recording's at
// every checkpoint, so a replay shows whether it is the trial as it was).
// The whole file is read, checked and indexed when the player is made; on
// the tick it decodes one block at a time into buffers sized once, so the
// tick never allocates.
#pragma once
#include <atomic>
#include <cstdint>
#include <span>
#include <vector>

#include "hapsim/recording/recording_reader.h"
#include "hapsim/runtime/tick_input_source.h"
#include "hapsim/runtime/tick_listener.h"

namespace hapsim::service {

class RecordingPlayer final : public TickInputSource, public TickListener {
 public:
  // Plays from the recorded tick `start_tick` on (the header's first tick:
  // the whole trial). Throws RecordingError for an unreadable file header
  // and std::invalid_argument when the recording holds no tick at or after
  // start_tick.
  RecordingPlayer(std::vector<std::uint8_t> bytes, std::uint64_t start_tick);

  const RecordingSummary& summary() const { return summary_; }
  const RecordingHeader& header() const { return summary_.header; }
  std::span<const std::uint8_t> bytes() const { return bytes_; }  // the whole file

  // Tick worker (TickInputSource, TickListener).
  bool Next(TickInput* in) override;
  void Rewind() override;
  bool TakeStep() override;
  void OnTick(const TickOutcome& tick) override;

  // Any thread.
  void RequestSteps(std::uint32_t ticks) { steps_.fetch_add(ticks, std::memory_order_relaxed); }
  struct Progress {
    std::uint64_t next_tick = 0;  // the recorded tick the next input is
    std::uint64_t checkpoints_matched = 0;
    std::uint64_t checkpoints_diverged = 0;
    bool ended = false;  // every recorded input given
  };
  Progress progress() const;

 private:
  struct Block {
    std::span<const std::uint8_t> payload;
    std::uint64_t first_tick = 0;
    std::uint32_t count = 0;
  };
  void Seek(std::uint64_t tick);  // tick worker, or the constructor
  bool LoadBlock(std::size_t index);

  std::vector<std::uint8_t> bytes_;
  RecordingSummary summary_;
  std::vector<Block> blocks_;
  std::vector<RecordedCheckpoint> checkpoints_;  // in tick order
  TickBlockDecoder decoder_;

  // Tick worker.
  std::size_t block_ = 0;  // the block `ticks_` holds
  std::span<const TickInput> ticks_;
  std::size_t in_block_ = 0;  // the next input's index in it
  std::size_t next_checkpoint_ = 0;
  bool gave_input_ = false;  // this tick stepped a recorded input
  std::uint64_t given_tick_ = 0;

  std::atomic<std::uint32_t> steps_{0};
  std::atomic<std::uint64_t> next_tick_{0}, matched_{0}, diverged_{0};
  std::atomic<bool> ended_{false};
};

}  // namespace hapsim::service
