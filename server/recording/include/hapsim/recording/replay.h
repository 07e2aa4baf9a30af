// Re-runs a trial recording: builds the scene its header names, feeds it
// every recorded TickInput through the same StepScene() the session used,
// and compares the scene's StateHash() with the recording's at every
// checkpoint. The core is deterministic, so a good recording reaches every
// hash exactly; the first mismatch stops the replay (the state has diverged
// and everything after it would be meaningless).
#pragma once
#include <cstdint>
#include <functional>
#include <limits>
#include <memory>
#include <optional>
#include <span>

#include "hapsim/core/scenes/scene.h"
#include "hapsim/recording/recording_reader.h"

namespace hapsim::service {

struct ReplayOptions {
  std::uint64_t until_tick = std::numeric_limits<std::uint64_t>::max();  // stop after this tick
  // Where to start: a fresh scene before the trial's first tick (the
  // default), or `scene` restored (a Scene::SaveState() of the trial's state
  // before `next_tick`; the ticks before it are read and checked, not run).
  // Borrowed for the call.
  struct From {
    const core::Scene* scene = nullptr;
    std::uint64_t next_tick = 0;
  };
  From from;
  // After each tick's step (to watch, pace or step through a replay).
  std::function<void(const TickInput&, const core::Scene&)> after_tick;
  // After each checkpoint reached with the recorded hash (to keep states to seek to).
  std::function<void(const RecordedCheckpoint&, const core::Scene&)> after_matched_checkpoint;
};

struct HashMismatch {
  std::uint64_t tick = 0;
  std::uint64_t recorded = 0;
  std::uint64_t replayed = 0;
};

struct ReplayResult {
  RecordingSummary summary;
  std::unique_ptr<core::Scene> scene;  // as after the last tick run
  std::uint64_t ticks_run = 0;         // stepped (from options.from on)
  std::uint64_t checkpoints_matched = 0;
  std::optional<HashMismatch> mismatch;
  std::optional<TickInput> last_input;  // the last tick run
  double elapsed_s = 0.0;               // wall time of the replay
  bool ok() const { return !mismatch; }
};

// Throws RecordingError when the file header is unreadable and
// std::invalid_argument when its scene cannot be built.
ReplayResult Replay(std::span<const std::uint8_t> recording, const ReplayOptions& options = {});

}  // namespace hapsim::service
