// Resting skin in the cutting scene (msm/resting_nodes.h): side by side
// with the full step (rest_force_N = 0) on the same stroke, every node and
// the tool's force stay within the bound the rest force sets; skin nothing
// disturbs costs nothing; a cut wakes what it unbalanced.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "cutting_strokes.h"
#include "hapsim/core/scenes/cutting/cutting_scene.h"
#include "scene_tick.h"

namespace hapsim::core {
namespace {

// The synthetic device's `cut` stroke (approach, press to depth, draw 20 mm
// along x at 10 mm/s, lift), then 1.5 s with the tool gone while the wound
// settles.
std::vector<ToolInput> StrokeThenLetGo(double depth_m) {
  std::vector<ToolInput> out = test::ScalpelStroke({-0.01, 0.0003}, 0.0, 0.02, depth_m);
  out.insert(out.end(), 1500, ToolInput{});
  return out;
}

struct SideBySide {
  double max_node_error_m = 0.0;  // over every live node and tick
  double max_force_error_N = 0.0;
  double rms_force_error_N = 0.0;
  double rms_force_N = 0.0;           // the full step's
  double incision_m[2] = {0.0, 0.0};  // full, resting
  double peak_force_N = 0.0;
  double mean_awake_fraction = 0.0;  // integrated nodes / free live nodes
  std::int32_t awake_at_end = 0;
};

SideBySide RunSideBySide(double rest_force_N, double depth_m) {
  CuttingParams full_params, rest_params;
  full_params.rest_force_N = 0.0;
  rest_params.rest_force_N = rest_force_N;
  CuttingScene full{full_params}, resting{rest_params};
  SideBySide r;
  const auto tools = StrokeThenLetGo(depth_m);
  double awake_sum = 0.0, error2_sum = 0.0, force2_sum = 0.0;
  for (const auto& t : tools) {
    full.Step(t, kTick_s);
    resting.Step(t, kTick_s);
    error2_sum += (full.ToolForce_W_N() - resting.ToolForce_W_N()).squaredNorm();
    force2_sum += full.ToolForce_W_N().squaredNorm();
    const MsmModel& m = full.Skin().model;
    EXPECT_EQ(m.node_live, resting.Skin().model.node_live) << "not the same cut";
    for (Eigen::Index i = 0; i < m.num_nodes; ++i)
      if (m.node_live[static_cast<std::size_t>(i)])
        r.max_node_error_m =
            std::max(r.max_node_error_m, (full.Skin().state.x_m.col(i) - resting.Skin().state.x_m.col(i)).norm());
    r.max_force_error_N = std::max(r.max_force_error_N, (full.ToolForce_W_N() - resting.ToolForce_W_N()).norm());
    r.peak_force_N = std::max(r.peak_force_N, full.ToolForce_W_N().norm());
    awake_sum += static_cast<double>(resting.AwakeNodes()) / static_cast<double>(full.AwakeNodes());
  }
  r.mean_awake_fraction = awake_sum / static_cast<double>(tools.size());
  r.rms_force_error_N = std::sqrt(error2_sum / static_cast<double>(tools.size()));
  r.rms_force_N = std::sqrt(force2_sum / static_cast<double>(tools.size()));
  r.incision_m[0] = full.Incision().Length_m();
  r.incision_m[1] = resting.Incision().Length_m();
  r.awake_at_end = resting.AwakeNodes();
  return r;
}

// A resting node's net force stays under rest_force_N. What holds a whole
// patch of skin in the plane against a small uniform pull is only its
// anchors (anchor_stiffness_N_per_m per node; the springs move with it), so
// a resting patch is within ~rest_force / anchor_k of the full step's
// position, and the blade's penalty spring turns that into ~contact_k x
// that on the tool. That is an estimate, not a bound: the error also
// scatters with the blade's contacts. On the validation's stroke (1.5 mm
// deep) and over the parameter's range (up to the default, 1e-5 N),
// measured: nodes at 1.23 and 1.05, forces at 1.10 and 0.91 of the
// estimate; the check allows 1.5x. (Beyond the range it grows faster:
// 1.5x at 3e-5 N, 2.8x at 1e-4 N.)
TEST(CuttingResting, EveryNodeAndTheToolForceStayWithinTheRestForcesEstimateOfTheFullStep) {
  const CuttingParams defaults;
  for (const double rest_force_N : {defaults.rest_force_N, 0.3 * defaults.rest_force_N}) {
    const SideBySide r = RunSideBySide(rest_force_N, 0.0015);
    const double node_estimate_m = rest_force_N / defaults.anchor_stiffness_N_per_m;
    const double force_estimate_N = defaults.contact_stiffness_N_per_m * node_estimate_m;
    std::printf(
        "rest force %.1e N: node error %.2f um (estimate %.1f), tool force error %.2f mN (estimate %.1f) "
        "of a %.3f N peak; %.1f %% of the nodes integrated on average, %d awake at the end\n",
        rest_force_N, 1e6 * r.max_node_error_m, 1e6 * node_estimate_m, 1e3 * r.max_force_error_N,
        1e3 * force_estimate_N, r.peak_force_N, 100.0 * r.mean_awake_fraction, r.awake_at_end);
    EXPECT_LE(r.max_node_error_m, 1.5 * node_estimate_m) << rest_force_N;
    EXPECT_LE(r.max_force_error_N, 1.5 * force_estimate_N) << rest_force_N;
    // What it buys: most of the skin rests through a stroke and its settling.
    EXPECT_LT(r.mean_awake_fraction, 0.7) << rest_force_N;
  }
}

// The synthetic device's default cut is 5 mm deep: the blade's side pushes
// the lips hard, and there the full model itself is sensitive — a
// rest_force_N of 1e-7 N (sub-micrometre differences) grew to 0.9 mm
// node-to-node differences within the stroke. Node-wise comparison says
// nothing there; what the trainee feels does: the tool force over the
// stroke. Measured at the default: RMS difference 0.45 % of the RMS force
// (1e-7 N: 0.02 %), the largest single-tick difference 263 mN of a 1.59 N
// peak (1e-7 N: 4 mN), the same incision.
TEST(CuttingResting, ADeepCutFeelsTheSameOverTheStroke) {
  const SideBySide r = RunSideBySide(CuttingParams{}.rest_force_N, 0.005);
  std::printf(
      "5 mm deep: tool force RMS difference %.3f %% of the RMS force, largest %.1f mN of a %.3f N peak; "
      "incision %.3f / %.3f mm; %.1f %% of the nodes integrated on average\n",
      100.0 * r.rms_force_error_N / r.rms_force_N, 1e3 * r.max_force_error_N, r.peak_force_N, 1e3 * r.incision_m[0],
      1e3 * r.incision_m[1], 100.0 * r.mean_awake_fraction);
  EXPECT_LE(r.rms_force_error_N, 0.01 * r.rms_force_N);
  EXPECT_EQ(r.incision_m[0], r.incision_m[1]);
}

TEST(CuttingResting, SkinNothingDisturbsIsNeverIntegrated) {
  CuttingScene scene{CuttingParams{}};
  ToolInput above;
  above.valid = true;
  above.tip_W_m = Eigen::Vector3d(0.0, 0.0, 0.004);  // 4 mm over the skin
  for (int k = 0; k < 200; ++k) scene.Step(k % 2 ? above : ToolInput{}, kTick_s);
  EXPECT_EQ(scene.AwakeNodes(), 0);
  const CuttingScene fresh{CuttingParams{}};
  const MsmModel& m = fresh.Skin().model;
  for (Eigen::Index i = 0; i < m.num_nodes; ++i)
    if (m.node_live[static_cast<std::size_t>(i)] && !m.fixed[static_cast<std::size_t>(i)]) {
      ASSERT_EQ(scene.Skin().state.x_m.col(i), fresh.Skin().state.x_m.col(i)) << "node " << i;
    }
}

TEST(CuttingResting, APressWakesTheSkinAroundTheTipAndItRestsAgainAfterwards) {
  CuttingScene scene{CuttingParams{}};
  ToolInput press;
  press.valid = true;
  press.orientation_W = Eigen::Quaterniond::Identity();
  press.tip_W_m = Eigen::Vector3d(0.0, 0.0, -0.0003);  // 0.3 mm into the skin: pressing, not cutting
  for (int k = 0; k < 100; ++k) scene.Step(press, kTick_s);
  EXPECT_FALSE(scene.Cutting());
  const std::int32_t pressed = scene.AwakeNodes();
  EXPECT_GT(pressed, 4);  // more than the tip's cell: its neighbours were pulled
  const std::int32_t free_nodes = [&] {
    CuttingParams full;
    full.rest_force_N = 0.0;
    return CuttingScene{full}.AwakeNodes();
  }();
  EXPECT_LT(pressed, free_nodes / 2);  // a press is local
  for (int k = 0; k < 3000; ++k) scene.Step(ToolInput{}, kTick_s);
  EXPECT_EQ(scene.AwakeNodes(), 0);
}

}  // namespace
}  // namespace hapsim::core
