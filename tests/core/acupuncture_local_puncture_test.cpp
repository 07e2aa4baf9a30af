// The acupuncture scene's force models say where the pressed layer will give
// way (release_penetration_m, tip_release_penetration_m), so a device that
// renders a model a round trip old still feels the puncture at the depth the
// physics punctures, not a round trip later and harder.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <vector>

#include "hapsim/core/haptics/local_force_model.h"
#include "hapsim/core/scenes/acupuncture/acupuncture_scene.h"
#include "scene_tick.h"

namespace hapsim::core {
namespace {

constexpr double kInsertSpeed_m_per_s = 10e-3;  // the scripted insertion's
constexpr double kStep_m = kInsertSpeed_m_per_s * kTick_s;

struct Insertion {
  std::vector<LocalForceModel> models;  // after each tick
  std::vector<double> tip_z_m;          // the tick's tip
  std::vector<double> force_z_N;        // the physics' force on the tip
  std::vector<std::size_t> puncture_ticks;
};

// Straight down the z axis at 10 mm/s, from 1 mm above the skin to 14 mm deep (through skin and fat).
Insertion InsertVertically() {
  AcupunctureScene scene{AcupunctureParams{}};
  Insertion in;
  std::uint64_t seen = scene.EventsTotal();
  for (double z = 1e-3; z > -14e-3; z -= kStep_m) {
    ToolInput tool;
    tool.valid = true;
    tool.tip_W_m = {0, 0, z};
    tool.velocity_W_m_per_s = {0, 0, -kInsertSpeed_m_per_s};
    scene.Step(tool, kTick_s);
    const auto events = scene.Events();
    for (std::uint64_t e = seen; e < scene.EventsTotal(); ++e)
      if (events[events.size() - (scene.EventsTotal() - e)].kind == SceneEventKind::kPuncture)
        in.puncture_ticks.push_back(in.models.size());
    seen = scene.EventsTotal();
    in.models.push_back(scene.ForceModel());
    in.tip_z_m.push_back(z);
    in.force_z_N.push_back(scene.ToolForce_W_N().z());
  }
  return in;
}

// Where along z the model says the pressed layer gives (the tip position at release).
double PredictedReleaseZ_m(const LocalForceModel& m) {
  if (m.state == ContactState::kContact) return (m.anchor_W_m - m.release_penetration_m * m.normal_W).z();
  return (m.tip_anchor_W_m - m.tip_release_penetration_m * m.normal_W).z();
}

TEST(AcupunctureLocalPuncture, EveryModelOfThePressBeforeAPunctureNamesItsDepthWithinOneTickOfTravel) {
  const Insertion in = InsertVertically();
  ASSERT_GE(in.puncture_ticks.size(), 2u);  // skin, then fat
  std::size_t previous = 0;
  for (const std::size_t p : in.puncture_ticks) {
    // The physics punctures on the first tick whose tip is at or past the
    // depth where the net's table reaches the puncture force, so the tip is
    // then less than one tick of travel past it.
    double worst_m = 0.0;
    int pressed_models = 0;
    for (std::size_t t = std::max(previous, p >= 300 ? p - 300 : 0); t < p; ++t) {  // this layer's press
      const LocalForceModel& m = in.models[t];
      const bool pressing = (m.state == ContactState::kContact && m.release_penetration_m > 0.0) ||
                            (m.state == ContactState::kPunctured && m.tip_release_penetration_m > 0.0);
      if (!pressing) continue;
      ++pressed_models;
      const double past_m = PredictedReleaseZ_m(m) - in.tip_z_m[p];  // > 0: the tip at puncture is below it
      EXPECT_GE(past_m, -1e-9) << "tick " << t << " before the puncture at tick " << p;
      EXPECT_LT(past_m, kStep_m + 1e-9) << "tick " << t << " before the puncture at tick " << p;
      worst_m = std::max(worst_m, std::abs(past_m));
    }
    EXPECT_GE(pressed_models, 50) << "puncture at tick " << p;
    std::printf("puncture at tick %zu (z %.4f mm): %d models before it name the depth within %.2f um\n", p,
                in.tip_z_m[p] * 1e3, pressed_models, worst_m * 1e6);
    previous = p + 1;
  }
}

// A device rendering the model from a round trip ago (20 and 100 ms: 0.2 and
// 1 mm of press behind) feels each puncture on the tick the physics does.
TEST(AcupunctureLocalPuncture, AStaleModelPopsOnTheTickThePhysicsPunctures) {
  const Insertion in = InsertVertically();
  const Eigen::Vector3d v(0, 0, -kInsertSpeed_m_per_s);
  for (const std::size_t delay_ticks : {20u, 100u}) {
    for (const std::size_t p : in.puncture_ticks) {
      ASSERT_GT(p, delay_ticks + 1);
      // The physics' force drops at the puncture: before it, pressed; at it, the layer is gone.
      ASSERT_GT(in.force_z_N[p - 1], in.force_z_N[p] + 0.1) << "the force drops at the puncture";
      const auto rendered_z_N = [&](std::size_t t) {
        return EvaluateLocalForce(in.models[t - delay_ticks], {0, 0, in.tip_z_m[t]}, v).z();
      };
      const double before_N = rendered_z_N(p - 1), at_N = rendered_z_N(p);
      const double physics_drop_N = in.force_z_N[p - 1] - in.force_z_N[p];
      // At the puncture: what is left is what the physics leaves (the tunnel's damping, the layer
      // beyond untouched), within 0.05 N.
      EXPECT_NEAR(at_N, in.force_z_N[p], 0.05) << "delay " << delay_ticks << " ms, puncture at tick " << p;
      // And the tick before, the stale spring still pressed: the pop comes on the physics' tick. Its
      // size: a linear spring from a model 100 ms old undershoots a net that stiffens as it deepens
      // (the fat's: 0.12 of 0.21 N), so at least half the physics' drop.
      EXPECT_GE(before_N - at_N, 0.5 * physics_drop_N) << "delay " << delay_ticks << " ms, puncture at tick " << p;
      if (delay_ticks == 20) {  // 0.2 mm behind: the spring is the physics' within 10 %
        EXPECT_NEAR(before_N, in.force_z_N[p - 1], 0.1 * in.force_z_N[p - 1]) << "puncture at tick " << p;
      }
      std::printf("delay %zu ms, puncture at tick %zu: physics %.3f -> %.3f N, rendered %.3f -> %.3f N\n", delay_ticks,
                  p, in.force_z_N[p - 1], in.force_z_N[p], before_N, at_N);
    }
  }
}

TEST(LocalForceModelRelease, ASkinPressedToItsReleasePenetrationBecomesATunnel) {
  LocalForceModel m;
  m.state = ContactState::kContact;
  m.normal_W = {0, 0, 1};
  m.stiffness_N_per_m = 500.0;
  m.feedforward_W_N = {0.1, 0, 0};
  m.release_penetration_m = 2e-3;
  m.release_stiffness_N_per_m = 200.0;
  m.release_damping_Ns_per_m = 3.0;
  const Eigen::Vector3d down(0, 0, -0.01);
  // 1.9 mm: the skin's spring, 500 N/m x 1.9 mm = 0.95 N, and the feed-forward.
  const Eigen::Vector3d f1 = EvaluateLocalForce(m, {0, 0, -1.9e-3}, Eigen::Vector3d::Zero());
  EXPECT_NEAR(f1.z(), 0.95, 1e-12);
  EXPECT_NEAR(f1.x(), 0.1, 1e-12);
  // 2 mm and beyond, 0.5 mm off the axis, moving down 10 mm/s: the tunnel's
  // lateral spring (200 N/m x 0.5 mm) and axial damping (3 N s/m x 10 mm/s).
  const Eigen::Vector3d f2 = EvaluateLocalForce(m, {5e-4, 0, -2.5e-3}, down);
  EXPECT_NEAR(f2.x(), -0.1, 1e-12);
  EXPECT_NEAR(f2.y(), 0.0, 1e-12);
  EXPECT_NEAR(f2.z(), 0.03, 1e-12);
  m.release_penetration_m = 0.0;  // the layer never gives in this model: the spring all the way
  EXPECT_NEAR(EvaluateLocalForce(m, {0, 0, -2.5e-3}, Eigen::Vector3d::Zero()).z(), 1.25, 1e-12);
}

TEST(LocalForceModelRelease, TheNextLayerUnderTheTipStopsPushingAtItsReleasePenetration) {
  LocalForceModel m;
  m.state = ContactState::kPunctured;
  m.normal_W = {0, 0, 1};
  m.tip_anchor_W_m = {0, 0, -0.01};
  m.tip_stiffness_N_per_m = 400.0;
  m.tip_release_penetration_m = 1.5e-3;
  EXPECT_NEAR(EvaluateLocalForce(m, {0, 0, -0.0114}, Eigen::Vector3d::Zero()).z(), 0.56, 1e-12);  // 1.4 mm
  EXPECT_EQ(EvaluateLocalForce(m, {0, 0, -0.0116}, Eigen::Vector3d::Zero()).z(), 0.0);            // 1.6 mm: gone
}

}  // namespace
}  // namespace hapsim::core
