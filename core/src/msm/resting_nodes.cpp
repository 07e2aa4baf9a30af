#include "hapsim/core/msm/resting_nodes.h"

#include <algorithm>
#include <cmath>

#include "msm_kernels.h"

namespace hapsim::core {

namespace {

// The force of spring sp on node i (at x_i, its far end j), in the
// kernel's form: F_i = [k (1 - L0/l) + c (d . dv) / l^2] d, d = x_j - x_i;
// kStatic: as if both ends stood still (no damping term).
template <bool kStatic>
inline Eigen::Vector3d SpringForceOn_N(const MsmModel& m, const MsmState& s, std::int32_t i, const Eigen::Vector3d& xi,
                                       std::size_t sp, std::int32_t j) {
  const Eigen::Vector3d d = s.x_m.col(j) - xi;
  const double inv_l = 1.0 / std::sqrt(d.squaredNorm() + detail::kTinyLength2_m2);
  double scale = m.spring_k_N_per_m[sp] * (1.0 - m.spring_rest_m[sp] * inv_l);
  if constexpr (!kStatic)
    scale += m.spring_c_Ns_per_m[sp] * d.dot(s.v_m_per_s.col(j) - s.v_m_per_s.col(i)) * (inv_l * inv_l);
  return scale * d;
}

// Node i's own terms but its absolute damping: external and residual
// forces, gravity and anchors.
inline Eigen::Vector3d OwnTerms_N(const MsmModel& m, const MsmState& s, std::int32_t i, const Eigen::Vector3d& xi) {
  return s.f_ext_N.col(i) + s.f_residual_N.col(i) + m.mass_kg[i] * m.gravity_m_per_s2 - m.anchor_k_sum_N_per_m[i] * xi +
         m.anchor_kp_sum_N.col(i);
}

inline std::int32_t FarEnd(const MsmModel& m, std::size_t sp, std::int32_t i) {
  return m.spring_i[sp] == i ? m.spring_j[sp] : m.spring_i[sp];
}

// The step's force on node i; kStatic: as if every node stood still (no
// damping terms), the force left once a node and its neighbours rest.
template <bool kStatic>
Eigen::Vector3d NodeForce_N(const MsmModel& m, const MsmState& s, std::int32_t i) {
  const Eigen::Vector3d xi = s.x_m.col(i);
  Eigen::Vector3d f = Eigen::Vector3d::Zero();
  const std::int32_t* springs = m.SpringsOf(i);
  for (std::int32_t e = 0; e < m.DegreeOf(i); ++e) {
    const auto sp = static_cast<std::size_t>(springs[e]);
    f += SpringForceOn_N<kStatic>(m, s, i, xi, sp, FarEnd(m, sp, i));
  }
  f += OwnTerms_N(m, s, i, xi);
  if constexpr (!kStatic) f -= m.absolute_damping_Ns_per_m[i] * s.v_m_per_s.col(i);
  return f;
}

}  // namespace

Eigen::Vector3d NetNodeForce_N(const MsmModel& m, const MsmState& s, std::int32_t i) {
  return NodeForce_N<false>(m, s, i);
}

Eigen::Vector3d StaticNodeForce_N(const MsmModel& m, const MsmState& s, std::int32_t i) {
  return NodeForce_N<true>(m, s, i);
}

RestingNodes::RestingNodes(const MsmModel& model, const RestConfig& config)
    : config_(config),
      awake_(static_cast<std::size_t>(model.num_nodes), 0),
      quiet_steps_(static_cast<std::size_t>(model.num_nodes), 0),
      region_(MakeLocalRegion(model)),
      spring_in_region_(static_cast<std::size_t>(model.spring_capacity), 0),
      node_touched_(static_cast<std::size_t>(model.num_nodes), 0),
      still_springs_N_(Eigen::Matrix3Xd::Zero(3, model.num_nodes)),
      still_springs_known_(static_cast<std::size_t>(model.num_nodes), 0) {
  just_rested_.reserve(static_cast<std::size_t>(model.num_nodes));
  woken_.reserve(static_cast<std::size_t>(model.num_nodes));
}

bool RestingNodes::Unbalanced(const MsmModel& model, const MsmState& state, std::int32_t node) const {
  return NetNodeForce_N(model, state, node).squaredNorm() > config_.force_N * config_.force_N;
}

// Damping holds a creeping node in balance while it moves; stopped, it
// would be pulled on: judged as it will stand, with every velocity zero.
bool RestingNodes::UnbalancedAtRest(const MsmModel& model, const MsmState& state, std::int32_t node) const {
  return StaticNodeForce_N(model, state, node).squaredNorm() > config_.force_N * config_.force_N;
}

// The force of node i's springs to nodes that stand still (resting or
// fixed: their positions and zero velocities do not change), kept until one
// of them wakes or rests or the topology changes (ForgetStillSprings).
const double* RestingNodes::StillSpringsForce_N(const MsmModel& m, const MsmState& s, std::int32_t i) {
  const auto n = static_cast<std::size_t>(i);
  if (!still_springs_known_[n]) {
    const Eigen::Vector3d xi = s.x_m.col(i);
    const std::int32_t* springs = m.SpringsOf(i);
    Eigen::Vector3d still = Eigen::Vector3d::Zero();
    for (std::int32_t e = 0; e < m.DegreeOf(i); ++e) {
      const auto sp = static_cast<std::size_t>(springs[e]);
      const std::int32_t j = FarEnd(m, sp, i);
      if (!awake_[static_cast<std::size_t>(j)]) still += SpringForceOn_N<false>(m, s, i, xi, sp, j);
    }
    still_springs_N_.col(i) = still;
    still_springs_known_[n] = 1;
  }
  return still_springs_N_.col(i).data();
}

// The step's spring pass has left, in f, the forces of the region's springs
// on its resting neighbours: with their kept forces from the springs to
// nodes that stand still and their own terms (summed as the node pass would),
// that is the net force the step would apply to each at the state it starts
// from. Those pulled past force_N wake and are integrated in this step, their
// entries completed with their still springs. Judged first and woken after,
// so that every judgement and completion sees the springs the pass computed.
std::int32_t RestingNodes::JudgeBoundary(const MsmModel& m, const MsmState& s, double* f) {
  woken_.clear();
  const detail::NodeTerms terms(m, s);
  const double* x = s.x_m.data();
  const double* v = s.v_m_per_s.data();
  const double limit2 = config_.force_N * config_.force_N;
  for (const std::int32_t i : region_.touched_nodes) {
    const auto n = static_cast<std::size_t>(i);
    if (awake_[n] || m.fixed[n] || !m.node_live[n]) continue;
    const double* still = StillSpringsForce_N(m, s, i);
    const double* fi = f + kSpringForceStride * n;
    double net2 = 0.0;
    for (int c = 0; c < 3; ++c) {
      const double net = terms.Total(fi[c] + still[c], x, v, i, c);
      net2 += net * net;
    }
    if (net2 > limit2) woken_.push_back(i);
  }
  // Every entry is completed before any node wakes: a wake changes its
  // neighbours' kept sums, and a spring between two woken nodes was in no
  // pass — each takes it from its own sum.
  for (const std::int32_t i : woken_) {
    double* fi = f + kSpringForceStride * static_cast<std::size_t>(i);
    const double* still = StillSpringsForce_N(m, s, i);
    for (int c = 0; c < 3; ++c) fi[c] += still[c];
  }
  for (const std::int32_t i : woken_) Wake(m, i);
  judged_in_step_ = true;
  return static_cast<std::int32_t>(region_.active_nodes.size());
}

StepReport RestingNodes::Step(const MsmModel& model, MsmState& state, double dt_s, IntegratorChoice method,
                              MsmWorkspace& ws) {
  struct Listener final : SpringPassListener {
    RestingNodes& resting;
    const MsmModel& model;
    const MsmState& state;
    Listener(RestingNodes& r, const MsmModel& m, const MsmState& s) : resting(r), model(m), state(s) {}
    std::int32_t AfterSpringPass(double* f) override { return resting.JudgeBoundary(model, state, f); }
  } listener(*this, model, state);
  const LocalRegion& region = Region(model);
  // Right after a rest check (and a reset) Settle judges, after the step.
  const bool judge_in_step = steps_since_rest_check_ != 0;
  const StepReport report = StepMsmLocal(model, state, dt_s, method, ws, region, judge_in_step ? &listener : nullptr);
  Settle(model, state);
  return report;
}

// The node woke or rests: the kept sums of its own springs and of its
// neighbours' (one of whose far ends changed side) are recomputed when next
// needed.
void RestingNodes::ForgetStillSprings(const MsmModel& m, std::int32_t node) {
  still_springs_known_[static_cast<std::size_t>(node)] = 0;
  const std::int32_t* springs = m.SpringsOf(node);
  for (std::int32_t e = 0; e < m.DegreeOf(node); ++e)
    still_springs_known_[static_cast<std::size_t>(FarEnd(m, static_cast<std::size_t>(springs[e]), node))] = 0;
}

// The node, its springs and their far ends join the current region.
void RestingNodes::AddToRegion(const MsmModel& m, std::int32_t node) {
  auto touch = [&](std::int32_t i) {
    if (!node_touched_[static_cast<std::size_t>(i)]) {
      node_touched_[static_cast<std::size_t>(i)] = 1;
      region_.touched_nodes.push_back(i);
    }
  };
  region_.active_nodes.push_back(node);
  touch(node);
  const std::int32_t* springs = m.SpringsOf(node);
  for (std::int32_t e = 0; e < m.DegreeOf(node); ++e) {
    const auto s = static_cast<std::size_t>(springs[e]);
    if (spring_in_region_[s]) continue;
    spring_in_region_[s] = 1;
    region_.springs.push_back(static_cast<std::int32_t>(s));
    touch(m.spring_i[s] == node ? m.spring_j[s] : m.spring_i[s]);
  }
}

// Empties the region's lists (and, by them, its marks) and marks it stale.
void RestingNodes::ClearRegion() {
  for (const std::int32_t s : region_.springs) spring_in_region_[static_cast<std::size_t>(s)] = 0;
  for (const std::int32_t i : region_.touched_nodes) node_touched_[static_cast<std::size_t>(i)] = 0;
  region_.active_nodes.clear();
  region_.springs.clear();
  region_.touched_nodes.clear();
  region_stale_ = true;
}

void RestingNodes::RebuildRegion(const MsmModel& m) {
  ClearRegion();
  for (std::int32_t i = 0; i < m.num_nodes; ++i)
    if (awake_[static_cast<std::size_t>(i)]) AddToRegion(m, i);
  region_stale_ = false;
}

void RestingNodes::Wake(const MsmModel& model, std::int32_t node) {
  const auto n = static_cast<std::size_t>(node);
  if (awake_[n] || model.fixed[n] || !model.node_live[n]) return;
  awake_[n] = 1;
  quiet_steps_[n] = 0;
  ++awake_count_;
  ForgetStillSprings(model, node);
  if (!region_stale_) AddToRegion(model, node);
}

void RestingNodes::RestAll() {
  just_rested_.clear();
  std::fill(awake_.begin(), awake_.end(), 0);
  std::fill(quiet_steps_.begin(), quiet_steps_.end(), 0);
  std::fill(still_springs_known_.begin(), still_springs_known_.end(), 0);
  awake_count_ = 0;
  steps_since_rest_check_ = 0;
  region_stale_ = true;
}

void RestingNodes::AfterTopologyEdit(const MsmModel& model, const MsmState& state, const Eigen::AlignedBox3d& box) {
  // Spring indices moved, so the region's spring list names other springs
  // now: every spring mark is cleared, then the lists by themselves.
  std::fill(spring_in_region_.begin(), spring_in_region_.end(), 0);
  region_.springs.clear();
  std::fill(still_springs_known_.begin(), still_springs_known_.end(), 0);  // springs and nodes changed
  ClearRegion();
  WakeUnbalancedIn(model, state, box);
}

void RestingNodes::WakeUnbalancedIn(const MsmModel& model, const MsmState& state, const Eigen::AlignedBox3d& box) {
  if (box.isEmpty()) return;
  for (std::int32_t i = 0; i < model.num_nodes; ++i) {
    const auto n = static_cast<std::size_t>(i);
    if (!awake_[n] && model.node_live[n] && !model.fixed[n] && box.contains(model.x0_m.col(i)) &&
        Unbalanced(model, state, i))
      Wake(model, i);
  }
}

const LocalRegion& RestingNodes::Region(const MsmModel& model) {
  if (region_stale_) RebuildRegion(model);
  return region_;
}

void RestingNodes::Settle(const MsmModel& model, MsmState& state) {
  just_rested_.clear();
  const double speed2 = config_.speed_m_per_s * config_.speed_m_per_s;
  for (const std::int32_t i : region_.active_nodes) {
    const auto n = static_cast<std::size_t>(i);
    quiet_steps_[n] = state.v_m_per_s.col(i).squaredNorm() < speed2 ? quiet_steps_[n] + 1 : 0;
  }
  // Resting spring neighbours of the nodes that moved: pulled past force_N,
  // they wake (joining the region; the ones they touch are judged after
  // the next step, as the full step would move them then). A step that
  // told JudgeBoundary judged them at its start instead, from its own pass;
  // but a rest check changes the region: its step and the one after it are
  // judged here, as a step that did not tell.
  const bool rest_check_now = steps_since_rest_check_ + 1 >= kRestCheckSteps;
  if (!judged_in_step_ || rest_check_now) {
    const std::size_t boundary_end = region_.touched_nodes.size();
    for (std::size_t k = 0; k < boundary_end; ++k) {
      const std::int32_t i = region_.touched_nodes[k];
      const auto n = static_cast<std::size_t>(i);
      if (!awake_[n] && !model.fixed[n] && model.node_live[n] && Unbalanced(model, state, i)) Wake(model, i);
    }
  }
  judged_in_step_ = false;
  if (++steps_since_rest_check_ < kRestCheckSteps) return;
  steps_since_rest_check_ = 0;
  // Quiet long enough and nothing pulls it: it rests (and leaves the region).
  for (const std::int32_t i : region_.active_nodes) {
    const auto n = static_cast<std::size_t>(i);
    if (quiet_steps_[n] < config_.quiet_steps || UnbalancedAtRest(model, state, i)) continue;
    awake_[n] = 0;
    quiet_steps_[n] = 0;
    --awake_count_;
    state.v_m_per_s.col(i).setZero();
    ForgetStillSprings(model, i);
    region_stale_ = true;
    just_rested_.push_back(i);
  }
}

}  // namespace hapsim::core
