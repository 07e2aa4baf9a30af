// What a scene shows the service after each Step() — the force model, the
// tool force, the events and the status — kept in one struct, and the one
// base class that serves Scene's output getters from it. Every scene derives
// from SceneWithOutputs, fills outputs_ in Step() and clears it with
// FinishReset(); the getters are written once, here.
#pragma once
#include <Eigen/Core>
#include <cstdint>
#include <memory>
#include <span>
#include <stdexcept>
#include <string>

#include "hapsim/core/haptics/local_force_model.h"
#include "hapsim/core/scenes/event_log.h"
#include "hapsim/core/scenes/scene.h"
#include "hapsim/core/scenes/scene_state_hash.h"

namespace hapsim::core {

// What one Step() produced: filled by Step(), read by the Scene getters.
struct SceneOutputs {
  LocalForceModel force_model;                               // what the device renders until the next tick
  Eigen::Vector3d tool_force_W_N = Eigen::Vector3d::Zero();  // the tissue's force on the tool [N]
  EventLog events;                                           // bounded: Step() never allocates
  SceneStatus status;
  ResetEpoch reset_epoch;  // the running totals at the last Reset() (StateHash)
};

// Scene::RestoreState() for a scene S: the saved copy assigned to it.
// Assignment keeps this scene's capacities (a vector assigned fewer
// elements than it holds room for keeps its room), so the restored scene's
// Step() never allocates and the cutting scene keeps room for new nodes; a
// copy would have neither.
template <class S>
void AssignSavedState(S& scene, const Scene& saved) {
  const auto* same = dynamic_cast<const S*>(&saved);
  if (same == nullptr) {
    throw std::invalid_argument(std::string("a saved state of another kind of scene cannot be restored into ") +
                                std::string(scene.Name()));
  }
  scene = *same;
}

// The base of every scene: Scene's output getters, served from outputs_.
class SceneWithOutputs : public Scene {
 public:
  LocalForceModel ForceModel() const final { return outputs_.force_model; }
  Eigen::Vector3d ToolForce_W_N() const final { return outputs_.tool_force_W_N; }
  std::span<const SceneEvent> Events() const final { return outputs_.events.View(); }
  std::uint64_t EventsTotal() const final { return outputs_.events.TotalPushed(); }
  const SceneStatus& Status() const final { return outputs_.status; }

 protected:
  // No tool force, a free force model, no layer, depth 0: the outputs of a
  // scene nothing touches.
  void ClearStepOutputs() {
    outputs_.tool_force_W_N.setZero();
    outputs_.force_model = LocalForceModel{};
    outputs_.status.current_layer = -1;
    outputs_.status.tip_depth_m = 0.0;
  }

  // The tail every Reset() shares, called once the scene's own state is back
  // at its initial values (sim time 0): the outputs cleared, a kReset event,
  // and the totals StateHash() counts from restarted here (EventsTotal() and
  // numerical_resets keep running; see Scene::StateHash).
  void FinishReset() {
    ClearStepOutputs();
    outputs_.events.Push({SimTime_s(), SceneEventKind::kReset, -1, Eigen::Vector3d::Zero()});
    outputs_.reset_epoch = ResetEpoch::Now(*this);
  }

  // A blow-up the scene recovered from at sim time t_s: counted and logged.
  void LogNumericalReset(double t_s) {
    ++outputs_.status.numerical_resets;
    outputs_.events.Push({t_s, SceneEventKind::kReset, -1, Eigen::Vector3d::Zero()});
  }

  SceneOutputs outputs_;
};

}  // namespace hapsim::core
