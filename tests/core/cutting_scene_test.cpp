// The cutting scene through its Scene interface, driven by scalpel strokes:
// the incision is cut live and cleanly (every mesh invariant, mass and rest
// area kept), residual stress opens the wound, the device feels nothing in
// air, a push when pressing and the cutting drag's law while cutting; the
// same stroke gives the same state; strokes off the patch, over an earlier
// wound and a NaN pose mid-cut are handled; cutting allocates nothing.
#include <cmath>
#include <numbers>

#include <gtest/gtest.h>

#include "allocation_counter.h"
#include "hapsim/core/scenes/cutting/cutting_scene.h"
#include "scene_tick.h"
#include "skin_invariants.h"

namespace hapsim::core {
namespace {

// A scalpel stroke as the synthetic device's `cut` script draws it: approach
// from 5 mm above at speed, press to depth, draw `length` along `heading`,
// lift; the blade leans 30° back against the stroke.
std::vector<ToolInput> Stroke(Eigen::Vector2d entry, double heading_rad, double length_m, double depth_m = 0.0015,
                              double speed_m_per_s = 0.01) {
  std::vector<ToolInput> out;
  const Eigen::Vector2d d(std::cos(heading_rad), std::sin(heading_rad));
  const Eigen::Vector3d up(-0.5 * d.x(), -0.5 * d.y(), std::sqrt(0.75));
  const Eigen::Quaterniond q = Eigen::Quaterniond::FromTwoVectors(Eigen::Vector3d::UnitZ(), up);
  auto add = [&](Eigen::Vector3d tip, Eigen::Vector3d v) {
    ToolInput t;
    t.valid = true;
    t.tip_W_m = tip;
    t.orientation_W = q;
    t.velocity_W_m_per_s = v;
    out.push_back(t);
  };
  const double step = speed_m_per_s * kTick_s;
  for (double z = 0.005; z > -depth_m; z -= step) add({entry.x(), entry.y(), z}, {0, 0, -speed_m_per_s});
  for (double u = 0.0; u <= length_m; u += step)
    add({entry.x() + u * d.x(), entry.y() + u * d.y(), -depth_m}, {speed_m_per_s * d.x(), speed_m_per_s * d.y(), 0});
  const Eigen::Vector2d end = entry + length_m * d;
  for (double z = -depth_m; z < 0.005; z += step) add({end.x(), end.y(), z}, {0, 0, speed_m_per_s});
  return out;
}

void Drive(Scene& s, const std::vector<ToolInput>& tools) {
  for (const auto& t : tools) s.Step(t, kTick_s);
}

int CountEvents(const Scene& s, SceneEventKind kind) {
  int n = 0;
  for (const auto& e : s.Events()) n += e.kind == kind;
  return n;
}

TEST(CuttingScene, AStraightStrokeCutsAnIncisionAlongItKeepingTheMeshSound) {
  CuttingScene scene{CuttingParams{}};
  Drive(scene, Stroke({-0.01, 0.0003}, 0.0, 0.02));
  EXPECT_EQ(CountEvents(scene, SceneEventKind::kCutStart), 1);
  ASSERT_EQ(CountEvents(scene, SceneEventKind::kCutEnd), 1);
  double length = 0.0;
  for (const auto& e : scene.Events())
    if (e.kind == SceneEventKind::kCutEnd) length = e.value;
  // Committed in 1.6 mm segments: the incision stops within one segment of the stroke's end.
  EXPECT_GT(length, 0.02 - scene.Params().segment_length_m - 1e-9);
  EXPECT_LE(length, 0.02 + 1e-9);
  EXPECT_FALSE(scene.CutTotals().refused);
  EXPECT_EQ(scene.CutTotals().skipped_triangles, 0u);
  EXPECT_EQ(scene.CutTotals().springs_refused, 0u);  // every wound triangle got its edge springs
  const CuttingParams& p = scene.Params();
  EXPECT_EQ(test::Violation(scene.Skin(), p.patch_length_m * p.patch_width_m, true), "");
  EXPECT_GT(scene.Skin().lip_nodes.size(), 2 * 20u);
}

// Residual stress opens the wound: at the incision's middle, the two lips
// (the wound nodes at the same curve point) move apart, and stay apart.
TEST(CuttingScene, ResidualStressOpensTheWound) {
  CuttingScene scene{CuttingParams{}};
  Drive(scene, Stroke({-0.01, 0.0003}, 0.0, 0.02));
  const SkinMesh& skin = scene.Skin();
  // The pair of lip nodes nearest the middle (x = 0) with the same rest position.
  std::uint32_t a = kNoSlot, b = kNoSlot;
  double best = 1e9;
  for (const std::uint32_t u : skin.lip_nodes)
    for (const std::uint32_t w : skin.lip_nodes)
      if (u < w && (skin.model.x0_m.col(u) - skin.model.x0_m.col(w)).norm() < 1e-12 &&
          std::abs(skin.model.x0_m(0, u)) < best) {
        best = std::abs(skin.model.x0_m(0, u));
        a = u, b = w;
      }
  ASSERT_NE(a, kNoSlot);
  const double width_now = (skin.state.x_m.col(a) - skin.state.x_m.col(b)).norm();
  ToolInput away;  // the tool gone: the wound relaxes under residual stress alone
  for (int k = 0; k < 1500; ++k) scene.Step(away, kTick_s);
  const double width_settled = (skin.state.x_m.col(a) - skin.state.x_m.col(b)).norm();
  EXPECT_GT(width_now, 1e-5);
  EXPECT_GT(width_settled, 1e-4);  // a visible gape (docs/validation.md has the curve)
  EXPECT_LT(width_settled, 0.005);
}

TEST(CuttingScene, TheDeviceFeelsNothingInAirAPushWhenPressingAndTheDragLawWhileCutting) {
  CuttingScene scene{CuttingParams{}};
  const auto stroke = Stroke({-0.01, 0.0003}, 0.0, 0.02);
  bool saw_free = false, saw_contact = false, saw_cutting = false;
  for (const auto& t : stroke) {
    scene.Step(t, kTick_s);
    const LocalForceModel m = scene.ForceModel();
    const Eigen::Vector3d f = scene.ToolForce_W_N();
    // The model the device renders reproduces the physics force at the tip.
    EXPECT_LT((EvaluateLocalForce(m, t.tip_W_m, t.velocity_W_m_per_s) - f).norm(), 1e-9);
    if (t.tip_W_m.z() > 0.001) {
      EXPECT_EQ(m.state, ContactState::kFree);
      EXPECT_EQ(f.norm(), 0.0);
      saw_free = true;
    }
    if (m.state == ContactState::kContact && f.z() > 0.0) saw_contact = true;
    if (m.state == ContactState::kCutting && t.velocity_W_m_per_s.x() > 0.0) {
      saw_cutting = true;
      // Along the incision: -(F_c tanh(v / v_s) + c v), v = 10 mm/s.
      const double v = 0.01;
      const double drag = scene.Params().cut_force_N * std::tanh(v / kDragSmoothingSpeed_m_per_s) +
                          scene.Params().cut_damping_Ns_per_m * v;
      EXPECT_NEAR((EvaluateLocalForce(m, t.tip_W_m, t.velocity_W_m_per_s) -
                                                     m.feedforward_W_N).dot(m.drag_direction_W),
                  -drag, 1e-12);
      EXPECT_GT(m.drag_direction_W.x(), 0.99);  // the incision runs along +x
    }
  }
  EXPECT_TRUE(saw_free && saw_contact && saw_cutting);
}

TEST(CuttingScene, TheSameStrokeGivesTheSameStateHash) {
  CuttingScene a{CuttingParams{}}, b{CuttingParams{}};
  const auto stroke = Stroke({-0.012, -0.0021}, 0.4, 0.018);
  Drive(a, stroke);
  Drive(b, stroke);
  EXPECT_EQ(a.StateHash(), b.StateHash());
  CuttingScene c{CuttingParams{}};
  auto shifted = stroke;
  for (auto& t : shifted) t.tip_W_m.y() += 1e-6;
  Drive(c, shifted);
  EXPECT_NE(a.StateHash(), c.StateHash());
}

TEST(CuttingScene, StrokesOffThePatchOverAWoundAndANanPoseBreakNothing) {
  CuttingScene scene{CuttingParams{}};
  Drive(scene, Stroke({0.02, 0.0}, 0.0, 0.02));            // runs off the patch's +x border
  Drive(scene, Stroke({-0.01, -0.008}, std::numbers::pi / 2, 0.016));  // a second incision
  Drive(scene, Stroke({-0.016, -0.002}, 0.1, 0.02));        // crossing the second
  auto with_nan = Stroke({-0.01, 0.01}, 0.0, 0.01);
  with_nan[with_nan.size() / 2].tip_W_m.x() = std::nan("");  // mid-cut
  Drive(scene, with_nan);
  EXPECT_GE(CountEvents(scene, SceneEventKind::kCutEnd), 4);
  EXPECT_EQ(scene.Status().numerical_resets, 0u);
  EXPECT_EQ(test::Violation(scene.Skin(), 0.0, false), "");
  EXPECT_TRUE(scene.ToolForce_W_N().allFinite());
}

TEST(CuttingScene, CuttingAllocatesNothing) {
  CuttingScene scene{CuttingParams{}};
  const auto stroke = Stroke({-0.01, 0.0003}, 0.3, 0.02);
  std::uint64_t allocations = 0;
  {
    hapsim::test::ScopedAllocationCount counting;
    Drive(scene, stroke);
    scene.Reset();
    Drive(scene, stroke);
    allocations = counting.Count();
  }
  EXPECT_EQ(allocations, 0u);
  EXPECT_GT(scene.CutTotals().triangles_added, 100u);
}

}  // namespace
}  // namespace hapsim::core
