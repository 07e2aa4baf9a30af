// Resting nodes (msm/resting_nodes.h): the per-node force they judge by is
// the step's own force; a pull wakes the skin it moves and no more; once
// the pull is gone every node rests again.
#include "hapsim/core/msm/resting_nodes.h"

#include <gtest/gtest.h>

#include <cstdio>

#include "hapsim/core/msm/msm_forces.h"
#include "hapsim/core/msm/msm_step.h"
#include "hapsim/core/scenes/tissue_block/tissue_block.h"
#include "msm_test_models.h"

namespace hapsim::core {
namespace {

TEST(RestingNodes, TheNetNodeForceIsWhatComputeForcesGivesEveryFreeNode) {
  const MsmModel model = BuildMsmModel(test::IrregularNetDef());
  MsmState state = MakeMsmState(model);
  state.x_m += 1e-3 * Eigen::Matrix3Xd::Random(3, model.num_nodes);
  state.v_m_per_s = 0.05 * Eigen::Matrix3Xd::Random(3, model.num_nodes);
  state.f_ext_N.col(3) << 0.01, -0.02, 0.03;
  state.f_residual_N.col(4) << -0.005, 0.0, 0.004;
  Eigen::Matrix3Xd f;
  ComputeForces(model, state, state.x_m, state.v_m_per_s, f);
  for (std::int32_t i = 0; i < model.num_nodes; ++i) {
    if (model.fixed[static_cast<std::size_t>(i)]) continue;
    // Forces of ~1 N summed in another order: rounding only.
    EXPECT_LT((NetNodeForce_N(model, state, i) - f.col(i)).norm(), 1e-12) << "node " << i;
  }
}

constexpr int kGrid = 31;
constexpr std::int32_t kCentre = (kGrid / 2) * kGrid + kGrid / 2;

MsmModel RestingPatch() {
  TissueBlockParams p;
  p.grid_nodes = kGrid;
  return BuildMsmModel(MakeTissueGridDef(p));
}

// n steps of the resting update with `press_N` down on the centre node;
// marks in ever_awake the nodes any step integrated.
void StepResting(const MsmModel& model, MsmState& state, MsmWorkspace& ws, RestingNodes& resting, double press_N, int n,
                 std::vector<bool>& ever_awake) {
  const IntegratorChoice symplectic{IntegratorKind::kSymplecticEuler, 0.5};
  state.f_ext_N(2, kCentre) = -press_N;
  for (int k = 0; k < n; ++k) {
    if (press_N != 0.0) resting.Wake(model, kCentre);
    for (const std::int32_t i : resting.Region(model).active_nodes) ever_awake[static_cast<std::size_t>(i)] = true;
    resting.Step(model, state, 1e-3, symplectic, ws);
  }
}

TEST(RestingNodes, APullWakesTheTissueItMovesAndItAllRestsAgainWhenLetGo) {
  const MsmModel model = RestingPatch();
  MsmState state = MakeMsmState(model);
  MsmWorkspace ws = MakeMsmWorkspace(model);
  RestingNodes resting(model, RestConfig{});
  EXPECT_EQ(resting.AwakeCount(), 0);
  std::vector<bool> ever_awake(static_cast<std::size_t>(model.num_nodes), false);
  StepResting(model, state, ws, resting, 0.5, 100, ever_awake);
  EXPECT_LT(state.x_m(2, kCentre), model.x0_m(2, kCentre) - 1e-4);  // it moved, 0.1 mm at least
  // Every node that moved was integrated (a resting node never moves), and
  // the pull reached past the centre's own neighbours; the fixed rim never.
  for (std::int32_t i = 0; i < model.num_nodes; ++i)
    if (state.x_m.col(i) != model.x0_m.col(i)) {
      EXPECT_TRUE(ever_awake[static_cast<std::size_t>(i)]) << i;
    }
  EXPECT_TRUE(ever_awake[kCentre + 2] && ever_awake[kCentre + 2 * kGrid]);
  EXPECT_FALSE(ever_awake[0]);
  // Let go: the patch swings back and settles, and then nothing is integrated.
  StepResting(model, state, ws, resting, 0.0, 5000, ever_awake);
  EXPECT_EQ(resting.AwakeCount(), 0);
  EXPECT_EQ(state.v_m_per_s.cwiseAbs().maxCoeff(), 0.0);
  // At rest where the force is under the threshold: near its rest shape.
  EXPECT_LT((state.x_m - model.x0_m).cwiseAbs().maxCoeff(), 1e-4);
}

}  // namespace
}  // namespace hapsim::core

namespace hapsim::core {
namespace {

// An overdamped node creeping home on its anchor (k = 1 N/m, c = 3 N*s/m:
// a 3 s time constant) is quiet long before it is home, and its damping
// balances the anchor's pull while it creeps: it must not rest until the
// pull itself is under the rest force (judged standing still).
TEST(RestingNodes, ACreepHeldInBalanceByDampingRestsOnlyOnceThePullIsSmall) {
  const double k = 1.0, c = 3.0;
  const MsmModel model = test::AnchoredNode(0.02, k, c);
  MsmState state = MakeMsmState(model);
  MsmWorkspace ws = MakeMsmWorkspace(model);
  RestingNodes resting(model, RestConfig{});
  state.x_m(0, 0) = 1e-3;  // 1 mm out, released at rest
  resting.Wake(model, 0);
  const IntegratorChoice symplectic{IntegratorKind::kSymplecticEuler, 0.5};
  double x_when_quiet = -1.0;
  for (int step = 0; step < 30000 && resting.AwakeCount() > 0; ++step) {
    resting.Step(model, state, 1e-3, symplectic, ws);
    if (x_when_quiet < 0.0 && std::abs(state.v_m_per_s(0, 0)) < RestConfig{}.speed_m_per_s)
      x_when_quiet = state.x_m(0, 0);
  }
  // Quiet (under 0.1 mm/s) already ~0.3 mm out; it rested within the rest
  // force's reach of home, k x <= force_N.
  EXPECT_GT(x_when_quiet, 2e-4);
  EXPECT_EQ(resting.AwakeCount(), 0);
  EXPECT_LE(std::abs(state.x_m(0, 0)), RestConfig{}.force_N / k);
}

}  // namespace
}  // namespace hapsim::core

namespace hapsim::core {
namespace {

// Step() judges the resting neighbours inside the step, from its spring
// pass and the kept sums of their still springs. Reference: the full walk
// of each one's springs (NetNodeForce_N) at the state the step starts from.
// Through a press, its release and the patch settling (nodes waking and
// resting throughout), every node the walk puts past force_N wakes and is
// integrated in that step. The only other nodes a step wakes are those
// judged after it, on the full walk: in a rest check's step and the one
// after it.
TEST(RestingNodes, TheNeighboursAStepWakesAreThoseTheFullWalkFindsPulledPastTheRestForce) {
  const MsmModel model = RestingPatch();
  MsmState state = MakeMsmState(model);
  MsmWorkspace ws = MakeMsmWorkspace(model);
  const RestConfig config;
  RestingNodes resting(model, config);
  const IntegratorChoice symplectic{IntegratorKind::kSymplecticEuler, 0.5};
  const auto n = static_cast<std::size_t>(model.num_nodes);
  std::int64_t woken_in_step = 0, woken_after = 0, rested = 0;
  for (int step = 0; step < 3000; ++step) {
    const bool pressing = step < 400 || (step >= 1200 && step < 1300);
    state.f_ext_N(2, kCentre) = pressing ? -0.5 : 0.0;
    if (pressing) resting.Wake(model, kCentre);
    std::vector<std::uint8_t> awake_before(n, 0), expect_woken(n, 0), near_threshold(n, 0);
    Eigen::Matrix3Xd net_before_N = Eigen::Matrix3Xd::Zero(3, model.num_nodes);
    for (std::size_t i = 0; i < n; ++i) awake_before[i] = resting.Awake(static_cast<std::int32_t>(i));
    const bool judged_in_step = resting.StepsSinceRestCheck() != 0;
    const bool judged_after = !judged_in_step || resting.StepsSinceRestCheck() + 1 == RestingNodes::kRestCheckSteps;
    // Predicted: the resting touched nodes the walk finds pulled past
    // force_N; a net force within 1e-9 of it is left out (rounding decides).
    for (const std::int32_t i : resting.Region(model).touched_nodes) {
      const auto u = static_cast<std::size_t>(i);
      if (!judged_in_step || awake_before[u] || model.fixed[u]) continue;
      net_before_N.col(i) = NetNodeForce_N(model, state, i);
      const double net_N = net_before_N.col(i).norm();
      expect_woken[u] = net_N > config.force_N;
      near_threshold[u] = std::abs(net_N - config.force_N) < 1e-9 * config.force_N;
    }
    const Eigen::Matrix3Xd x_before = state.x_m;
    resting.Step(model, state, 1e-3, symplectic, ws);
    for (std::size_t i = 0; i < n; ++i) {
      const auto col = static_cast<Eigen::Index>(i);
      const bool awake_after = resting.Awake(static_cast<std::int32_t>(i));
      rested += awake_before[i] && !awake_after;
      if (awake_before[i] || !awake_after || near_threshold[i]) {
        ASSERT_FALSE(expect_woken[i] && !awake_after) << "node " << i << " stayed resting in step " << step;
        continue;
      }
      if (expect_woken[i]) {
        ++woken_in_step;
        // Integrated with the whole force: symplectic Euler from rest,
        // v = h F / m (rounding only: the same terms in another order).
        const Eigen::Vector3d v_expected = 1e-3 * model.inv_mass_free_per_kg[col] * net_before_N.col(col);
        ASSERT_LT((state.v_m_per_s.col(col) - v_expected).norm(), 1e-9 * v_expected.norm())
            << "woken node " << i << " in step " << step;
      } else {
        ++woken_after;
        ASSERT_TRUE(judged_after) << "node " << i << " woke unpredicted in step " << step;
        EXPECT_EQ(state.x_m.col(col), x_before.col(col)) << "node " << i << " judged after step " << step;
      }
    }
  }
  // The run exercised it: many wakes in the step and many rests.
  std::printf("woken in the step %lld, after it %lld; rested %lld\n", static_cast<long long>(woken_in_step),
              static_cast<long long>(woken_after), static_cast<long long>(rested));
  EXPECT_GT(woken_in_step, 100);
  EXPECT_GT(rested, 100);
  EXPECT_EQ(resting.AwakeCount(), 0);
}

}  // namespace
}  // namespace hapsim::core
