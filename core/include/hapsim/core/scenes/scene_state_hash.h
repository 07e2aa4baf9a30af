// The part of Scene::StateHash() every scene shares: the outputs of the last
// step (force, force model, status) and the running totals counted from the
// last Reset(). Each scene adds its own state on top.
#pragma once
#include <cstdint>

#include "hapsim/core/scenes/scene.h"
#include "hapsim/core/state_hash.h"

namespace hapsim::core {

// EventsTotal() and Status().numerical_resets as they were right after the
// last Reset() (zero for a fresh scene). Reset() keeps those totals running,
// so the hash takes their increase since then (see Scene::StateHash).
struct ResetEpoch {
  std::uint64_t events_total = 0;
  std::uint64_t numerical_resets = 0;

  static ResetEpoch Now(const Scene& scene) {
    return {scene.EventsTotal(), scene.Status().numerical_resets};
  }
};

inline void AddToHash(StateHasher& h, const LocalForceModel& m) {
  h.Add(m.state).Add(m.anchor_W_m).Add(m.normal_W).Add(m.stiffness_N_per_m).Add(m.damping_Ns_per_m)
      .Add(m.feedforward_W_N);
  // Only a cutting model has drag (the other scenes' golden hashes stay as pinned).
  if (m.state == ContactState::kCutting) h.Add(m.drag_direction_W).Add(m.drag_N).Add(m.drag_damping_Ns_per_m);
  if (m.state == ContactState::kPunctured)
    h.Add(m.drag_N).Add(m.stick_W_m).Add(m.stick_stiffness_N_per_m).Add(m.tip_anchor_W_m).Add(m.tip_stiffness_N_per_m);
  // Only a model that renders a puncture locally has these (the others' hashes stay as pinned).
  if (m.release_penetration_m != 0.0)
    h.Add(m.release_penetration_m).Add(m.release_stiffness_N_per_m).Add(m.release_damping_Ns_per_m);
  if (m.tip_release_penetration_m != 0.0) h.Add(m.tip_release_penetration_m);
}

// Never allocates (ForceModel() returns a fixed-size value).
inline void AddCommonSceneState(StateHasher& h, const Scene& scene, const ResetEpoch& epoch) {
  h.Add(scene.SimTime_s());
  AddToHash(h, scene.ForceModel());
  h.Add(scene.ToolForce_W_N());
  const SceneStatus& status = scene.Status();
  h.Add(status.current_layer).Add(status.tip_depth_m);
  h.Add(scene.EventsTotal() - epoch.events_total).Add(status.numerical_resets - epoch.numerical_resets);
}

}  // namespace hapsim::core
