// Model-jump transition: when the server's model jumps (a contact appears
// or moves, a layer is punctured, a server restarts), switching to it at
// once would jolt the stylus by the whole jump within one tick. As VRPN's
// force server recovers a moved surface over a few servo cycles, the force
// instead blends from the replaced model to the new one, both evaluated at
// the current pose:
//   F = B + s (F_new(x) - B),  B = F_old(x) + r
// with s rising by 1/N per tick to 1 (N = model_transition_ticks), but by
// less when that would change F by more than jnd_fraction |F_previous| +
// jnd_floor_N in one tick (the just-noticeable step). r is zero except
// when a model arrives during a transition: it carries the unfinished part
// so the force stays continuous.
//
// A new model whose force at the stylus is within one such step of the
// model it replaces is not a jump (the server sends a model every physics
// tick, each close to the last): it is taken at once, or a running
// transition goes on towards it. Motion of the stylus itself changes F
// freely: only the switch between models is bounded. A non-finite force ends the
// transition and passes through to the chain's non-finite stage.
// Allocation-free (the replaced model is copied into a member).
#pragma once

#include <Eigen/Core>

#include "hapsim/core/haptics/local_force_model.h"

namespace hapsim::bridge {

struct TransitionConfig {
  int ticks = 10;  // N; 0: off
  double jnd_fraction = 0.07;
  double jnd_floor_N = 0.01;
};

class ModelTransition {
 public:
  explicit ModelTransition(const TransitionConfig& config) : config_(config) {}
  // A new model replaces `replaced`; new_W_N: the new model's force at the
  // stylus (x, v). Returns true when it is a jump and blending starts.
  bool Offer(const core::LocalForceModel& replaced, const Eigen::Vector3d& new_W_N, const Eigen::Vector3d& x_W_m,
             const Eigen::Vector3d& v_W_m_per_s);
  // This tick's force, model_W_N being the current model's at (x, v). Sets
  // *held_back when the JND bound slowed the blend this tick.
  Eigen::Vector3d Step(const Eigen::Vector3d& model_W_N, const Eigen::Vector3d& x_W_m,
                       const Eigen::Vector3d& v_W_m_per_s, bool* held_back);
  bool active() const { return active_; }
  // The largest change of the force the next tick may make [N].
  double StepBound() const { return config_.jnd_fraction * last_W_N_.norm() + config_.jnd_floor_N; }

 private:
  // Where the blend starts at (x, v): B = F_old(x) + r.
  Eigen::Vector3d Base(const Eigen::Vector3d& x_W_m, const Eigen::Vector3d& v_W_m_per_s) const;

  TransitionConfig config_;
  bool active_ = false;
  core::LocalForceModel from_;                              // the replaced model
  Eigen::Vector3d residual_W_N_ = Eigen::Vector3d::Zero();  // r
  double weight_ = 0.0;                                     // s in [0, 1]
  Eigen::Vector3d last_W_N_ = Eigen::Vector3d::Zero();      // last tick's force
};

}  // namespace hapsim::bridge
