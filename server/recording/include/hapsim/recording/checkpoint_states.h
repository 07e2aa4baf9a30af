// States of a replayed trial kept at some of its checkpoints (each reached
// with the recorded hash), so that seeking in a replay restores the nearest
// kept state at or before the target and re-runs the trial only from there.
// At most one state per stretch of `spacing_ticks` of the trial is kept, so
// a trial keeps at most trial_ticks / spacing_ticks + 1 states whatever its
// seeks. Not thread-safe: its owner serializes the calls.
#pragma once
#include <cstdint>
#include <map>
#include <memory>
#include <optional>

#include "hapsim/core/scenes/scene.h"

namespace hapsim::service {

class CheckpointStates {
 public:
  // first_tick: the trial's first tick; spacing_ticks >= 1.
  CheckpointStates(std::uint64_t first_tick, std::uint64_t spacing_ticks);

  // States a replay keeps over its trial by default (+1): the memory a
  // kept state takes is the scene's (docs/recording.md: 0.4 MB tissue_block
  // to 13 MB cutting), and a seek re-runs at most a 1/16 of the trial.
  static constexpr std::uint64_t kDefaultMaxStates = 16;

  // The spacing that keeps at most `max_states` + 1 states for a trial of `trial_ticks`,
  // and never closer than `min_spacing_ticks`.
  static std::uint64_t SpacingFor(std::uint64_t trial_ticks, std::uint64_t max_states, std::uint64_t min_spacing_ticks);

  struct Kept {
    const core::Scene* scene = nullptr;  // a Scene::SaveState(), owned here (valid while this lives)
    std::uint64_t next_tick = 0;         // the trial's state before this tick
  };
  // The kept state latest at or before the state before `next_tick`.
  std::optional<Kept> Nearest(std::uint64_t next_tick) const;

  // The scene as it is before `next_tick`: its state saved when its stretch
  // of the trial has none yet.
  void Offer(std::uint64_t next_tick, const core::Scene& scene);

  std::size_t size() const { return kept_.size(); }
  std::uint64_t spacing_ticks() const { return spacing_ticks_; }

 private:
  std::uint64_t Stretch(std::uint64_t next_tick) const;

  std::uint64_t first_tick_;
  std::uint64_t spacing_ticks_;
  std::map<std::uint64_t, std::pair<std::uint64_t, std::unique_ptr<const core::Scene>>>
      kept_;  // stretch -> (next tick, state)
};

}  // namespace hapsim::service
