// The tissue block sleeps (TissueBlockParams::rest_displacement_m): out of
// contact, once every node is within d_r of its rest position (each
// coordinate) and slower than v_r = d_r sqrt(anchor stiffness / node mass),
// the block is put exactly at rest and its steps are skipped until the tool
// touches it. Checked against the full step (rest_displacement_m = 0) driven
// by the same poses, side by side.
//
// What sleeping drops is the ring-down below d_r. At the moment the block is
// put at rest each coordinate moves by at most d_r; the full step's block,
// left ringing from there, is damped towards that same rest state. So a
// sleeping node sits within d_r of the full step's, and at the next touch the
// tool meets a surface at most d_r higher or lower, moving at most v_r
// slower or faster: a force difference of at most
// k_contact d_r + c_contact v_r, which the press then damps — unless the
// tool crosses the surface within d_r of a tick's pose (1 % of touches at
// 10 mm/s with the default d_r), where the first touch may come a tick
// apart (the grazing test below).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <vector>

#include "core/allocation_counter.h"
#include "core/scene_tick.h"
#include "hapsim/core/scenes/tissue_block/tissue_block.h"

namespace hapsim::core {
namespace {

ToolInput TipAt(double z_m, double vz_m_per_s = 0.0) {
  ToolInput t;
  t.valid = true;
  t.tip_W_m = Eigen::Vector3d(1.1e-3, -0.7e-3, z_m);  // inside a cell, off its nodes
  t.velocity_W_m_per_s = Eigen::Vector3d(0.0, 0.0, vz_m_per_s);
  return t;
}

TissueBlockParams Sleeping(double rest_displacement_m) {
  TissueBlockParams p;
  p.rest_displacement_m = rest_displacement_m;
  return p;
}

constexpr double kSpeed_m_per_s = 10e-3;

// hapsim-load's `insertion` script: from 10 mm above the surface down at
// 10 mm/s to 5 mm deep, held 0.5 s, back up at 10 mm/s. `offset_m` shifts
// every pose up: by half a tick's travel (5 um), no pose grazes the rest
// surface; with 0 the tick of first touch lands exactly on it.
std::vector<ToolInput> InsertionCycles(int cycles, double offset_m = 0.5 * kSpeed_m_per_s * kTick_s) {
  constexpr double kAbove_m = 10e-3, kDepth_m = 5e-3;
  constexpr int kHoldTicks = 500;
  std::vector<ToolInput> poses;
  const int down_ticks = static_cast<int>(std::lround((kAbove_m + kDepth_m) / kSpeed_m_per_s / kTick_s));
  for (int c = 0; c < cycles; ++c) {
    for (int k = 0; k < down_ticks; ++k)
      poses.push_back(TipAt(offset_m + kAbove_m - kSpeed_m_per_s * kTick_s * k, -kSpeed_m_per_s));
    for (int k = 0; k < kHoldTicks; ++k) poses.push_back(TipAt(offset_m - kDepth_m));
    for (int k = 0; k < down_ticks; ++k)
      poses.push_back(TipAt(offset_m - kDepth_m + kSpeed_m_per_s * kTick_s * k, kSpeed_m_per_s));
  }
  return poses;
}

struct Difference {
  double force_N = 0.0, node_m = 0.0, full_peak_force_N = 0.0;
  int ticks_asleep = 0;
  std::vector<double> node_m_per_tick;
};

Difference RunSideBySide(TissueBlockScene& full, TissueBlockScene& sleeping, const std::vector<ToolInput>& poses) {
  Difference d;
  for (const ToolInput& pose : poses) {
    full.Step(pose, kTick_s);
    sleeping.Step(pose, kTick_s);
    EXPECT_FALSE(full.Asleep());
    d.ticks_asleep += sleeping.Asleep() ? 1 : 0;
    d.force_N = std::max(d.force_N, (full.ToolForce_W_N() - sleeping.ToolForce_W_N()).norm());
    d.full_peak_force_N = std::max(d.full_peak_force_N, full.ToolForce_W_N().norm());
    d.node_m_per_tick.push_back((full.Vertices_m() - sleeping.Vertices_m()).cwiseAbs().maxCoeff());
    d.node_m = std::max(d.node_m, d.node_m_per_tick.back());
    EXPECT_EQ(full.SimTime_s(), sleeping.SimTime_s());
  }
  return d;
}

TEST(TissueBlockSleep, ThroughInsertionCyclesASleepingBlockFeelsAndSitsWhereTheFullStepHasIt) {
  const std::vector<ToolInput> poses = InsertionCycles(2);
  for (const double d_r : {TissueBlockParams{}.rest_displacement_m, 1e-6}) {
    SCOPED_TRACE(testing::Message() << "rest_displacement_m " << d_r);
    TissueBlockScene full(Sleeping(0.0)), sleeping(Sleeping(d_r));
    const Difference d = RunSideBySide(full, sleeping, poses);
    const TissueBlockParams& p = sleeping.Params();
    const double v_r = d_r * std::sqrt(p.anchor_stiffness_N_per_m / p.node_mass_kg);
    const double force_bound_N = p.contact_stiffness_N_per_m * d_r + p.contact_damping_Ns_per_m * v_r;
    std::printf(
        "d_r %.0e m: asleep %d of %zu ticks; worst node difference %.3g m, worst force difference %.3g N "
        "(bound %.3g N; peak %.3f N)\n",
        d_r, d.ticks_asleep, poses.size(), d.node_m, d.force_N, force_bound_N, d.full_peak_force_N);
    EXPECT_LE(d.node_m, d_r);
    EXPECT_LE(d.force_N, force_bound_N);
    EXPECT_GT(d.full_peak_force_N, 0.5);  // the presses are real
    // In the air 2 of each 3.5 s; the block rings down within ~0.2 s of release.
    EXPECT_GE(d.ticks_asleep, static_cast<int>(0.45 * static_cast<double>(poses.size())));
  }
}

// A pose exactly on the rest surface at the tick of first touch is a knife
// edge of the contact model itself: the full step's own rounding noise
// (~1e-18 m) decides whether that tick touches, and touching adds the
// damper's c_contact v_tool (8 mN here) at once. Against a block at exact
// rest the first touch can then come one tick apart: the force differs on
// that tick by at most the full step's force a tick after touching, and the
// difference dies out with the press's own damping.
TEST(TissueBlockSleep, APoseGrazingTheRestSurfaceMayTouchOneTickApartAndConverges) {
  const std::vector<ToolInput> poses = InsertionCycles(2, 0.0);
  TissueBlockScene full(Sleeping(0.0)), sleeping(TissueBlockParams{});
  const Difference d = RunSideBySide(full, sleeping, poses);
  const TissueBlockParams& p = sleeping.Params();
  const double one_tick_of_touch_N =
      p.contact_stiffness_N_per_m * kSpeed_m_per_s * kTick_s + p.contact_damping_Ns_per_m * kSpeed_m_per_s;
  std::printf("grazing: worst force difference %.3g N (one tick of touch %.3g N), worst node difference %.3g m\n",
              d.force_N, one_tick_of_touch_N, d.node_m);
  EXPECT_LE(d.force_N, one_tick_of_touch_N);
  // 100 ms after each first touch (ticks 1000 and 4500) the blocks agree within d_r again.
  for (const std::size_t after_touch : {1100u, 4600u})
    EXPECT_LE(d.node_m_per_tick[after_touch], p.rest_displacement_m) << "tick " << after_touch;
}

TEST(TissueBlockSleep, AsleepTheBlockStaysAtRestAllocatesNothingAndKeepsTheClock) {
  TissueBlockScene full(Sleeping(0.0)), sleeping(TissueBlockParams{});
  const std::vector<ToolInput> press = InsertionCycles(1);
  RunSideBySide(full, sleeping, press);
  for (int k = 0; k < 300; ++k) {  // 10 mm above: rings down, then sleeps
    full.Step(TipAt(10e-3), kTick_s);
    sleeping.Step(TipAt(10e-3), kTick_s);
  }
  ASSERT_TRUE(sleeping.Asleep());
  const Eigen::Matrix3Xd rest = sleeping.Vertices_m();
  EXPECT_EQ(rest, sleeping.Model().x0_m) << "asleep is exactly at rest";
  ToolInput lost;  // a device that stopped sending: no contact either
  std::uint64_t allocations = 0;
  {
    hapsim::test::ScopedAllocationCount count;
    for (int k = 0; k < 200; ++k) {
      const ToolInput& tool = k % 50 < 25 ? TipAt(5e-3) : lost;
      full.Step(tool, kTick_s);
      sleeping.Step(tool, kTick_s);
    }
    allocations = count.Count();
  }
  EXPECT_EQ(allocations, 0u);
  EXPECT_TRUE(sleeping.Asleep());
  EXPECT_EQ(sleeping.Vertices_m(), rest);
  EXPECT_EQ(sleeping.SimTime_s(), full.SimTime_s());
  EXPECT_EQ(sleeping.ToolForce_W_N().norm(), 0.0);
}

// The worst case for the bound: the tool comes back the moment the block
// falls asleep, while the full step's block still rings at up to d_r.
TEST(TissueBlockSleep, TouchedAsItFallsAsleepItWakesOnTheFullStepsTickWithinTheBound) {
  for (const double d_r : {TissueBlockParams{}.rest_displacement_m, 1e-6}) {
    SCOPED_TRACE(testing::Message() << "rest_displacement_m " << d_r);
    TissueBlockScene full(Sleeping(0.0)), sleeping(Sleeping(d_r));
    const TissueBlockParams& p = sleeping.Params();
    const double v_r = d_r * std::sqrt(p.anchor_stiffness_N_per_m / p.node_mass_kg);
    const double force_bound_N = p.contact_stiffness_N_per_m * d_r + p.contact_damping_Ns_per_m * v_r;
    // Pressed 3 mm, then let go: the tip jumps to 20 um above and waits there.
    for (int k = 0; k < 300; ++k) {
      full.Step(TipAt(-3e-3), kTick_s);
      sleeping.Step(TipAt(-3e-3), kTick_s);
    }
    int ticks = 0;
    for (; ticks < 2000 && !sleeping.Asleep(); ++ticks) {
      full.Step(TipAt(20e-6), kTick_s);
      sleeping.Step(TipAt(20e-6), kTick_s);
    }
    ASSERT_TRUE(sleeping.Asleep());
    const double ringing_m = (full.Vertices_m() - full.Model().x0_m).cwiseAbs().maxCoeff();
    // Straight back down at 10 mm/s (no pose grazing the surface) to 0.5 mm deep.
    int first_touch = -1;
    double worst_N = 0.0;
    for (int k = 0; k < 60; ++k) {
      const ToolInput tool = TipAt(20e-6 + 5e-6 - kSpeed_m_per_s * kTick_s * k, -kSpeed_m_per_s);
      full.Step(tool, kTick_s);
      sleeping.Step(tool, kTick_s);
      const double f_full = full.ToolForce_W_N().norm();
      if (first_touch < 0 && f_full > 0.0) first_touch = k;
      EXPECT_EQ(sleeping.Asleep(), first_touch < 0) << "tick " << k;
      worst_N = std::max(worst_N, std::abs(sleeping.ToolForce_W_N().norm() - f_full));
    }
    std::printf(
        "d_r %.0e m: asleep %d ticks after letting go with the full step's block %.3g m from rest; "
        "first touch %d ticks later; worst force difference %.3g N (bound %.3g N)\n",
        d_r, ticks, ringing_m, first_touch, worst_N, force_bound_N);
    EXPECT_GT(first_touch, 0);
    EXPECT_GT(ringing_m, 0.0);
    EXPECT_LE(worst_N, force_bound_N);
  }
}

TEST(TissueBlockSleep, ResetWakesIt) {
  TissueBlockScene s(TissueBlockParams{});
  s.Step(TipAt(5e-3), kTick_s);
  ASSERT_TRUE(s.Asleep()) << "built at rest, out of contact: asleep after one tick";
  s.Reset();
  EXPECT_FALSE(s.Asleep());
  s.Step(TipAt(5e-3), kTick_s);
  EXPECT_TRUE(s.Asleep());
}

}  // namespace
}  // namespace hapsim::core
