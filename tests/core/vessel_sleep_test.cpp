// The vessel wall sleeps (VesselParams::rest_speed_m_per_s): once every node
// has moved slower than the rest speed for kQuietStepsToSleep steps with the
// tip still or touching nothing, its step is skipped until the tip wakes it.
// Checked against the full step (rest_speed_m_per_s = 0) driven by the same
// poses, side by side.
//
// What sleeping neglects is the creep still under way when the wall fell
// asleep: every node slower than v_r = 1e-5 m/s, and the drag on each node
// (damping c = 15 /s) slows such a creep at least as fast as e^(-c t), so it
// would have covered at most v_r / c = 0.67 um more — the bound on where a
// sleeping node sits against the full step's. The force on the probe
// differs by what that creep would have changed in the contact.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>
#include <vector>

#include "core/allocation_counter.h"
#include "core/scene_tick.h"
#include "hapsim/core/scenes/vessel/vessel_scene.h"

namespace hapsim::core {
namespace {

ToolInput TipAt(double z_m) {
  ToolInput t;
  t.valid = true;
  t.tip_W_m = Eigen::Vector3d(3e-4, 0.0, z_m);  // off a node; the crest is at z = 0
  return t;
}

VesselParams FullStep() {
  VesselParams p;
  p.rest_speed_m_per_s = 0.0;
  return p;
}

// From 2 mm above first touch at 10 mm/s to `depth_m` past it, held 0.7 s,
// back up at 10 mm/s, then 0.7 s in the air (the wall settles in ~0.3-0.5 s).
// `still_ends`: the last pose of each phase in which the wall can stand
// still (the approach 1 mm above, the hold, the air).
std::vector<ToolInput> PressCycle(double probe_radius_m, double depth_m, std::vector<std::size_t>& still_ends) {
  std::vector<ToolInput> poses;
  const double touch_m = probe_radius_m;
  for (double z = touch_m + 2e-3; z > touch_m + 1e-3; z -= 1e-5) poses.push_back(TipAt(z));
  still_ends.push_back(poses.size() - 1);  // 1 mm above the crest (inflated: a little above z = 0)
  for (double z = touch_m + 1e-3; z > touch_m - depth_m; z -= 1e-5) poses.push_back(TipAt(z));
  for (int k = 0; k < 700; ++k) poses.push_back(TipAt(touch_m - depth_m));
  still_ends.push_back(poses.size() - 1);
  for (double z = touch_m - depth_m; z < touch_m + 2e-3; z += 1e-5) poses.push_back(TipAt(z));
  for (int k = 0; k < 700; ++k) poses.push_back(TipAt(touch_m + 2e-3));
  still_ends.push_back(poses.size() - 1);
  return poses;
}

struct Difference {
  double force_N = 0.0, node_m = 0.0;
  double full_peak_force_N = 0.0;
  int ticks_asleep = 0;
  std::vector<bool> asleep;  // per pose
};

Difference RunSideBySide(VesselScene& full, VesselScene& sleeping, const std::vector<ToolInput>& poses) {
  Difference d;
  for (const ToolInput& pose : poses) {
    full.Step(pose, kTick_s);
    sleeping.Step(pose, kTick_s);
    EXPECT_FALSE(full.Asleep());
    d.ticks_asleep += sleeping.Asleep() ? 1 : 0;
    d.asleep.push_back(sleeping.Asleep());
    d.force_N = std::max(d.force_N, (full.ToolForce_W_N() - sleeping.ToolForce_W_N()).norm());
    d.full_peak_force_N = std::max(d.full_peak_force_N, full.ToolForce_W_N().norm());
    d.node_m = std::max(d.node_m, (full.Nodes_m() - sleeping.Nodes_m()).colwise().norm().maxCoeff());
  }
  return d;
}

TEST(VesselSleep, ThroughAPressCycleASleepingWallFeelsAndSitsWhereTheFullStepHasIt) {
  for (const double depth_m : {1e-3, 3e-3}) {
    VesselScene full(FullStep());
    VesselScene sleeping(VesselParams{});
    std::vector<std::size_t> still_ends;
    const std::vector<ToolInput> poses = PressCycle(sleeping.Params().probe_radius_m, depth_m, still_ends);
    const Difference d = RunSideBySide(full, sleeping, poses);
    std::printf(
        "pressed %.0f mm: asleep %d of %zu ticks; against the full step: force %.2e N (peak %.3f N), nodes "
        "%.2e m\n",
        depth_m * 1e3, d.ticks_asleep, poses.size(), d.force_N, d.full_peak_force_N, d.node_m);
    // Asleep by the end of the approach, the hold and the time in the air.
    for (const std::size_t end : still_ends) EXPECT_TRUE(d.asleep[end]) << end;
    EXPECT_LT(d.node_m, 0.67e-6);  // v_r / c (above); seen 0.09-0.11 um
    EXPECT_LT(d.force_N, 1e-5);    // seen 0.4-2.9 uN (6.5 uN pressed 5 mm): ~1e-5 of the pressed force
  }
}

TEST(VesselSleep, TheWallWakesAtTheFirstTouchAndTheContactBeginsOnTheSameTick) {
  VesselScene full(FullStep());
  VesselScene sleeping(VesselParams{});
  const double touch_m = sleeping.Params().probe_radius_m;
  bool was_asleep_before_touch = false;
  for (double z = touch_m + 2e-3; z > touch_m - 0.5e-3; z -= 1e-5) {
    full.Step(TipAt(z), kTick_s);
    const bool asleep_before = sleeping.Asleep();
    sleeping.Step(TipAt(z), kTick_s);
    ASSERT_EQ(full.ForceModel().state, sleeping.ForceModel().state) << z;
    if (full.ToolForce_W_N().isZero(0.0)) continue;
    // The first tick with force: the sleeping wall woke for it.
    was_asleep_before_touch = asleep_before;
    EXPECT_FALSE(sleeping.Asleep());
    EXPECT_NEAR(sleeping.ToolForce_W_N().z(), full.ToolForce_W_N().z(), 1e-6);
    break;
  }
  EXPECT_TRUE(was_asleep_before_touch);
}

TEST(VesselSleep, AWallAsleepUnderTheProbeWakesWhenTheToolIsLostAndSpringsBackAsTheFullStepDoes) {
  VesselScene full(FullStep());
  VesselScene sleeping(VesselParams{});
  const double touch_m = sleeping.Params().probe_radius_m;
  std::vector<ToolInput> poses;
  for (double z = touch_m + 0.2e-3; z > touch_m - 1e-3; z -= 1e-5) poses.push_back(TipAt(z));
  for (int k = 0; k < 700; ++k) poses.push_back(TipAt(touch_m - 1e-3));
  RunSideBySide(full, sleeping, poses);
  ASSERT_TRUE(sleeping.Asleep());
  ASSERT_GT(sleeping.ToolForce_W_N().z(), 0.0);

  // The tool is lost (a bad reading): the contact goes, the wall wakes.
  const std::vector<ToolInput> lost(700, ToolInput{});
  full.Step(lost[0], kTick_s);
  sleeping.Step(lost[0], kTick_s);
  EXPECT_FALSE(sleeping.Asleep());
  EXPECT_EQ(sleeping.ToolForce_W_N(), Eigen::Vector3d::Zero());
  const Difference d = RunSideBySide(full, sleeping, lost);
  std::printf("tool lost under a 1 mm press: nodes within %.2e m of the full step over 700 ticks\n", d.node_m);
  EXPECT_LT(d.node_m, 0.67e-6);
  EXPECT_TRUE(sleeping.Asleep());  // sprung back, and asleep again

  sleeping.Reset();
  EXPECT_FALSE(sleeping.Asleep());
}

TEST(VesselSleep, ASleepingTickAllocatesNothingAndMovesNoNode) {
  VesselScene scene(VesselParams{});
  const double above_m = scene.Params().probe_radius_m + 2e-3;
  for (int k = 0; k < 2 * VesselScene::kQuietStepsToSleep; ++k) scene.Step(TipAt(above_m), kTick_s);
  ASSERT_TRUE(scene.Asleep());
  const Eigen::Matrix3Xd nodes = scene.Nodes_m();
  std::uint64_t allocations = 0;
  {
    hapsim::test::ScopedAllocationCount count;
    for (int k = 0; k < 100; ++k) scene.Step(TipAt(above_m - 1e-5 * k), kTick_s);  // moving, out of reach
    allocations = count.Count();
  }
  EXPECT_EQ(allocations, 0u);
  EXPECT_TRUE(scene.Asleep());
  EXPECT_EQ((scene.Nodes_m() - nodes).cwiseAbs().maxCoeff(), 0.0);
}

}  // namespace
}  // namespace hapsim::core
