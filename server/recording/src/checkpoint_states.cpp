#include "hapsim/recording/checkpoint_states.h"

#include <algorithm>

namespace hapsim::service {

CheckpointStates::CheckpointStates(std::uint64_t first_tick, std::uint64_t spacing_ticks)
    : first_tick_(first_tick), spacing_ticks_(std::max<std::uint64_t>(spacing_ticks, 1)) {}

std::uint64_t CheckpointStates::SpacingFor(std::uint64_t trial_ticks, std::uint64_t max_states,
                                           std::uint64_t min_spacing_ticks) {
  const std::uint64_t even = (trial_ticks + max_states - 1) / std::max<std::uint64_t>(max_states, 1);
  return std::max({even, min_spacing_ticks, std::uint64_t{1}});
}

std::uint64_t CheckpointStates::Stretch(std::uint64_t next_tick) const {
  return next_tick <= first_tick_ ? 0 : (next_tick - first_tick_) / spacing_ticks_;
}

std::optional<CheckpointStates::Kept> CheckpointStates::Nearest(std::uint64_t next_tick) const {
  auto it = kept_.upper_bound(Stretch(next_tick));
  while (it != kept_.begin()) {
    --it;
    if (it->second.first <= next_tick) return Kept{it->second.second.get(), it->second.first};
  }
  return std::nullopt;
}

void CheckpointStates::Offer(std::uint64_t next_tick, const core::Scene& scene) {
  auto& slot = kept_[Stretch(next_tick)];
  if (slot.second) return;
  slot = {next_tick, scene.SaveState()};
}

}  // namespace hapsim::service
