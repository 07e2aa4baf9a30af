#include "hapsim/recording/recording_player.h"

#include <algorithm>
#include <stdexcept>

namespace hapsim::service {

RecordingPlayer::RecordingPlayer(std::vector<std::uint8_t> bytes, std::uint64_t start_tick) : bytes_(std::move(bytes)) {
  RecordingVisitor visitor;
  visitor.checkpoint = [this](const RecordedCheckpoint& c) { checkpoints_.push_back(c); };
  visitor.record = [&](RecordKind kind, std::uint64_t offset, std::span<const std::uint8_t> payload,
                       std::uint64_t first_tick, std::uint32_t count) {
    if (kind != RecordKind::kTicks) return;
    blocks_.push_back({std::span<const std::uint8_t>(bytes_.data() + offset, payload.size()), first_tick, count});
  };
  summary_ = ReadRecording(bytes_, visitor);
  if (start_tick < summary_.header.first_tick || start_tick >= summary_.next_tick()) {
    throw std::invalid_argument("the recording holds ticks " + std::to_string(summary_.header.first_tick) + ".." +
                                std::to_string(summary_.next_tick()) + ", not " + std::to_string(start_tick));
  }
  decoder_.ReserveForLargestBlock();
  Seek(start_tick);
}

bool RecordingPlayer::LoadBlock(std::size_t index) {
  if (index >= blocks_.size()) return false;
  const Block& b = blocks_[index];
  ticks_ = decoder_.Decode(b.payload, b.first_tick, b.count);  // read and checked at construction: cannot throw
  block_ = index;
  in_block_ = 0;
  return true;
}

void RecordingPlayer::Seek(std::uint64_t tick) {
  const auto after = std::upper_bound(blocks_.begin(), blocks_.end(), tick,
                                      [](std::uint64_t t, const Block& b) { return t < b.first_tick; });
  const std::size_t index = static_cast<std::size_t>(std::max<std::ptrdiff_t>(0, after - blocks_.begin() - 1));
  ticks_ = {};
  if (LoadBlock(index)) in_block_ = static_cast<std::size_t>(tick - blocks_[index].first_tick);
  next_checkpoint_ = static_cast<std::size_t>(
      std::lower_bound(checkpoints_.begin(), checkpoints_.end(), tick,
                       [](const RecordedCheckpoint& c, std::uint64_t t) { return c.tick < t; }) -
      checkpoints_.begin());
  next_tick_.store(tick, std::memory_order_relaxed);
  ended_.store(false, std::memory_order_relaxed);
}

bool RecordingPlayer::Next(TickInput* in) {
  gave_input_ = false;
  if (in_block_ >= ticks_.size() && !LoadBlock(block_ + 1)) {
    ended_.store(true, std::memory_order_relaxed);
    return false;
  }
  *in = ticks_[in_block_++];
  gave_input_ = true;
  given_tick_ = in->tick;
  next_tick_.store(given_tick_ + 1, std::memory_order_relaxed);
  return true;
}

void RecordingPlayer::Rewind() { Seek(summary_.header.first_tick); }

bool RecordingPlayer::TakeStep() {
  std::uint32_t steps = steps_.load(std::memory_order_relaxed);
  while (steps > 0 && !steps_.compare_exchange_weak(steps, steps - 1, std::memory_order_relaxed)) {
  }
  return steps > 0;
}

void RecordingPlayer::OnTick(const TickOutcome& tick) {
  if (!gave_input_) return;
  gave_input_ = false;
  while (next_checkpoint_ < checkpoints_.size() && checkpoints_[next_checkpoint_].tick < given_tick_) {
    ++next_checkpoint_;
  }
  if (next_checkpoint_ < checkpoints_.size() && checkpoints_[next_checkpoint_].tick == given_tick_) {
    const bool same = tick.scene.StateHash() == checkpoints_[next_checkpoint_].state_hash;
    (same ? matched_ : diverged_).fetch_add(1, std::memory_order_relaxed);
    ++next_checkpoint_;
  }
}

RecordingPlayer::Progress RecordingPlayer::progress() const {
  Progress p;
  p.next_tick = next_tick_.load(std::memory_order_relaxed);
  p.checkpoints_matched = matched_.load(std::memory_order_relaxed);
  p.checkpoints_diverged = diverged_.load(std::memory_order_relaxed);
  p.ended = ended_.load(std::memory_order_relaxed);
  return p;
}

}  // namespace hapsim::service
