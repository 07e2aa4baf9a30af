// Resting nodes: the gingival paper's local update region (section 1: only
// nodes near the collision are updated) grown to wherever the tissue moves.
// A node rests — is left out of the step, its velocity zero — once its speed
// has stayed under `speed_m_per_s` for `quiet_steps` steps in a row and the
// force on it standing still is under `force_N` (checked every
// kRestCheckSteps; judged at zero velocity so that damping cannot hide a
// creep). A resting node wakes when the net force on it exceeds `force_N`
// (an awake neighbour moved and pulls it) or when the scene wakes it (the
// tool loads it, a cut changed its springs).
//
// Error estimate: a resting node's force is below force_N whenever it is
// checked — when it rests, after every step in which a spring neighbour was
// awake, and, near the edit, after a topology edit — and nothing else
// changes it. What holds a patch of resting nodes against a small common
// pull is its weakest support (in the cutting skin: the anchors), so it is
// about force_N / k_support from where the full step would hold it. The
// cutting scene measures the whole-mesh effect against the full step
// (tests/core/cutting_resting_test.cpp, docs/validation.md).
//
// Deterministic: the region's lists grow in the order nodes wake and are
// rebuilt in ascending node order, the same on every machine. Never
// allocates after construction.
#pragma once
#include <Eigen/Core>
#include <Eigen/Geometry>
#include <cstdint>
#include <vector>

#include "hapsim/core/msm/local_region.h"
#include "hapsim/core/msm/msm_model.h"
#include "hapsim/core/msm/msm_state.h"
#include "hapsim/core/msm/msm_step.h"

namespace hapsim::core {

struct RestConfig {
  double force_N = 1e-4;          // net force under which a node may rest and above which it wakes
  double speed_m_per_s = 1e-4;    // speed under which a node counts as quiet
  std::int32_t quiet_steps = 20;  // quiet steps in a row before it rests
};

// The net force the step would apply to free node i at the state: its
// springs (with their along-spring damping), external and residual forces,
// gravity, absolute damping and anchors — the terms of msm_kernels.h's
// spring pass and NodeTerms, in one node's terms.
Eigen::Vector3d NetNodeForce_N(const MsmModel& model, const MsmState& state, std::int32_t node);
// The same with every velocity zero (no damping terms): the force on the
// node once it and its neighbours stand still.
Eigen::Vector3d StaticNodeForce_N(const MsmModel& model, const MsmState& state, std::int32_t node);

class RestingNodes {
 public:
  RestingNodes() = default;
  // Every node resting (a model at rest in its initial state). Allocates.
  RestingNodes(const MsmModel& model, const RestConfig& config);

  const RestConfig& Config() const { return config_; }

  // The scene moves the node this step (contact on it): it is integrated.
  void Wake(const MsmModel& model, std::int32_t node);
  // Every node resting again (after a reset to a state at rest).
  void RestAll();
  // After a topology edit (spring indices move): the region is rebuilt, and
  // every free live resting node inside `box` (rest positions) whose net
  // force exceeds force_N wakes — the box must hold every node the edit
  // touched.
  void AfterTopologyEdit(const MsmModel& model, const MsmState& state, const Eigen::AlignedBox3d& box);
  // Every free live resting node inside `box` whose net force exceeds
  // force_N wakes (e.g. again once forces that changed with the edit are
  // refreshed).
  void WakeUnbalancedIn(const MsmModel& model, const MsmState& state, const Eigen::AlignedBox3d& box);

  // The step's region: the awake free nodes. Woken nodes join it at once
  // (O(degree) each); nodes that rest leave it at the next rebuild.
  const LocalRegion& Region(const MsmModel& model);
  // After the step on Region(): resting neighbours the step pulled wake;
  // every kRestCheckSteps, nodes quiet for quiet_steps and balanced rest.
  void Settle(const MsmModel& model, MsmState& state);
  // StepMsmLocal on Region(), then Settle(). With explicit or symplectic
  // Euler the resting neighbours are judged inside the step instead, from
  // the forces its spring pass leaves on them (the same net force, at the
  // same state, without walking their springs again): those pulled past
  // force_N are integrated in that step.
  StepReport Step(const MsmModel& model, MsmState& state, double dt_s, IntegratorChoice method, MsmWorkspace& ws);

  std::int32_t AwakeCount() const { return awake_count_; }
  // The nodes the last Settle() let rest: their last positions are where
  // they stand from now on.
  const std::vector<std::int32_t>& JustRested() const { return just_rested_; }
  bool Awake(std::int32_t node) const { return awake_[static_cast<std::size_t>(node)] != 0; }
  // For the scene's state hash: what decides the next steps besides x and v.
  const std::vector<std::uint8_t>& AwakeFlags() const { return awake_; }
  const std::vector<std::int32_t>& QuietSteps() const { return quiet_steps_; }
  std::int32_t StepsSinceRestCheck() const { return steps_since_rest_check_; }

  // Steps between the checks that let quiet nodes rest (and rebuild the
  // region without them).
  static constexpr std::int32_t kRestCheckSteps = 16;

 private:
  bool Unbalanced(const MsmModel& model, const MsmState& state, std::int32_t node) const;
  bool UnbalancedAtRest(const MsmModel& model, const MsmState& state, std::int32_t node) const;
  const double* StillSpringsForce_N(const MsmModel& model, const MsmState& state, std::int32_t node);
  std::int32_t JudgeBoundary(const MsmModel& model, const MsmState& state, double* spring_forces_N);
  void ForgetStillSprings(const MsmModel& model, std::int32_t node);
  void AddToRegion(const MsmModel& model, std::int32_t node);
  void ClearRegion();
  void RebuildRegion(const MsmModel& model);

  RestConfig config_;
  std::vector<std::uint8_t> awake_;        // (n)
  std::vector<std::int32_t> quiet_steps_;  // (n) consecutive quiet steps of an awake node
  std::vector<std::int32_t> just_rested_;  // reserved (n)
  std::vector<std::int32_t> woken_;        // reserved (n): JudgeBoundary's
  bool judged_in_step_ = false;            // JudgeBoundary ran since the last Settle
  std::int32_t awake_count_ = 0;
  std::int32_t steps_since_rest_check_ = 0;
  // The region and its membership marks; stale = rebuilt at the next Region().
  bool region_stale_ = true;
  LocalRegion region_;
  std::vector<std::uint8_t> spring_in_region_;  // (spring capacity)
  std::vector<std::uint8_t> node_touched_;      // (n)
  // Per resting node, the force [N] of its springs to nodes that stand
  // still, while known (JudgeBoundary adds it to what the pass computed).
  Eigen::Matrix3Xd still_springs_N_;               // (3 x n)
  std::vector<std::uint8_t> still_springs_known_;  // (n)
};

}  // namespace hapsim::core
