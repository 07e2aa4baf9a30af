// TickInput: everything one session tick reads, assembled once at the start
// of the tick (one input point per step). The step is
// a function of (scene, TickInput, period) alone — StepScene() below — so
// feeding the same TickInput sequence to a fresh scene reaches the same
// Scene::StateHash(). It is also the record a recording stores.
#pragma once
#include <cstdint>

#include "hapsim/core/scenes/scene.h"

namespace hapsim::service {

struct TickInput {
  std::uint64_t tick = 0;        // index of this tick since the session was created
  core::ToolInput tool;          // the device's newest pose; valid=false when none arrived
                                 // within the pose timeout (the tool is absent)
  std::uint32_t device_id = 0;   // the device that owns the session (0: none yet)
  std::uint64_t pose_seq = 0;    // seq of the pose in `tool` (echoed in the force model)
  bool fresh_pose = false;       // a pose newer than the previous tick's arrived (this tick
                                 // was clocked by the device); does not change the physics
  bool paused = false;           // the tissue is frozen this tick
  bool reset = false;            // back to the initial state before stepping
  // Scene parameter changes will join here when SessionService gains a
  // SetParameters call; today parameters are fixed at creation.
};

// The deterministic part of a tick: apply the control events, then step by
// one period unless paused.
inline void StepScene(core::Scene& scene, const TickInput& in, double period_s) {
  if (in.reset) scene.Reset();
  if (!in.paused) scene.Step(in.tool, period_s);
}

}  // namespace hapsim::service
