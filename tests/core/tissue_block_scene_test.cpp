// tissue_block: the scene the server runs first. Forces must be real
// (from the deformed mass-spring surface), consistent with the local force
// model sent to the device, deterministic and allocation-free per step.
#include "hapsim/core/scenes/tissue_block/tissue_block.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <memory>

#include "allocation_counter.h"
#include "hapsim/core/msm/msm_forces.h"
#include "hapsim/core/scenes/scene_builders.h"
#include "scene_tick.h"

namespace hapsim::core {
namespace {

ToolInput ToolAt(double x, double y, double z) {
  ToolInput t;
  t.valid = true;
  t.tip_W_m = {x, y, z};
  return t;
}

// Holds the tool still for `seconds`, so the tissue settles.
void Hold(Scene& s, const ToolInput& tool, double seconds) {
  for (int k = 0; k < static_cast<int>(std::lround(seconds / kTick_s)); ++k) s.Step(tool, kTick_s);
}

TEST(TissueBlock, BuiltByTheSceneFactoryWithDefaults) {
  auto scene = MakeScene({"tissue_block", {}});
  ASSERT_NE(scene, nullptr);
  EXPECT_EQ(scene->Name(), "tissue_block");
  EXPECT_EQ(scene->Topology().PartNames(), std::vector<std::string>{"tissue"});
  EXPECT_EQ(scene->Topology().Triangles().LiveCount(), 2u * 20 * 20);
  EXPECT_EQ(scene->Vertices_m().cols(), 21 * 21);
  EXPECT_EQ(scene->Topology().Vertices().LiveCount(), 21u * 21);
  EXPECT_EQ(scene->Status().layer_names, std::vector<std::string>{"tissue"});
}

TEST(TissueBlock, UnknownOrBadParametersThrowNamingTheKey) {
  EXPECT_THROW(MakeScene({"tissue_block", {{"stiffnes", 1.0}}}), std::invalid_argument);
  EXPECT_THROW(MakeScene({"tissue_block", {{"grid_nodes", 2.5}}}), std::invalid_argument);
  EXPECT_THROW(MakeScene({"tissue_block", {{"node_mass_kg", -1.0}}}), std::invalid_argument);
  EXPECT_THROW(MakeScene({"tissue_block", {{"integrator", 9}}}), std::invalid_argument);
  try {
    MakeScene({"tissue_block", {{"size_m", std::nan("")}}});
    FAIL() << "NaN size accepted";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("size_m"), std::string::npos) << e.what();
  }
}

TEST(TissueBlock, RefusesTimeStepAboveCriticalWithTheLimitInTheMessage) {
  // Explicit Euler is unstable at 1 ms with the default stiffness and mass.
  try {
    MakeScene({"tissue_block", {{"integrator", 0}}});
    FAIL() << "unstable dt accepted";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("critical step"), std::string::npos) << e.what();
  }
  // Backward Euler is unconditionally stable: same dt accepted.
  EXPECT_NO_THROW(MakeScene({"tissue_block", {{"integrator", 5}}}));
}

TEST(TissueBlock, ZeroForceAndNoMotionAtRest) {
  TissueBlockScene scene(TissueBlockParams{});
  Eigen::Matrix3Xd f;
  ComputeForces(scene.Model(), scene.State(), scene.State().x_m, scene.State().v_m_per_s, f);
  // Pre-stretched springs balance exactly on the regular grid (free nodes).
  double max_free_force_N = 0.0;
  for (int i = 0; i < f.cols(); ++i)
    if (!scene.Model().fixed[static_cast<std::size_t>(i)]) max_free_force_N = std::max(max_free_force_N, f.col(i).norm());
  EXPECT_LT(max_free_force_N, 1e-12);
  const Eigen::Matrix3Xd x0 = scene.Vertices_m();
  Hold(scene, ToolAt(0, 0, 0.01), 0.2);  // tool 10 mm above the surface
  EXPECT_EQ(scene.ToolForce_W_N().norm(), 0.0);
  EXPECT_EQ(scene.ForceModel().state, ContactState::kFree);
  EXPECT_LT((scene.Vertices_m() - x0).cwiseAbs().maxCoeff(), 1e-12);
}

TEST(TissueBlock, PressPushesBackAlongTheNormalWithPhysiologicalMagnitude) {
  TissueBlockScene scene(TissueBlockParams{});
  Hold(scene, ToolAt(0.0011, -0.0007, -0.005), 0.5);  // 5 mm press, off-node
  const Eigen::Vector3d f = scene.ToolForce_W_N();
  EXPECT_GT(f.z(), 0.0) << "tissue must push the tool up (out), opposite to the press";
  EXPECT_NEAR(f.head<2>().norm(), 0.0, 1e-12);
  // Design target: a 5 mm press of skin-like tissue gives 0.5-1.5 N.
  EXPECT_GT(f.z(), 0.5);
  EXPECT_LT(f.z(), 1.5);
  // The surface really deforms under the tip.
  EXPECT_LT(scene.Vertices_m().row(2).minCoeff(), -0.002);
  EXPECT_EQ(scene.Status().current_layer, 0);
  EXPECT_NEAR(scene.Status().tip_depth_m, 0.005, 1e-15);
}

TEST(TissueBlock, ForceGrowsMonotonicallyWithDepth) {
  double previous_N = 0.0;
  for (const double depth_m : {0.001, 0.002, 0.004, 0.006, 0.008}) {
    TissueBlockScene scene(TissueBlockParams{});
    Hold(scene, ToolAt(0, 0, -depth_m), 0.5);
    EXPECT_GT(scene.ToolForce_W_N().z(), previous_N) << "depth " << depth_m;
    previous_N = scene.ToolForce_W_N().z();
  }
}

TEST(TissueBlock, LocalForceModelReproducesTheToolForceAtTheTip) {
  TissueBlockScene scene(TissueBlockParams{});
  const ToolInput tool = ToolAt(0.002, 0.001, -0.004);
  Hold(scene, tool, 0.3);
  const LocalForceModel m = scene.ForceModel();
  ASSERT_EQ(m.state, ContactState::kContact);
  EXPECT_GT(m.stiffness_N_per_m, 0.0);
  // Series of penalty and tissue: never stiffer than the penalty spring.
  EXPECT_LE(m.stiffness_N_per_m, scene.Params().contact_stiffness_N_per_m);
  const Eigen::Vector3d f = EvaluateLocalForce(m, tool.tip_W_m, Eigen::Vector3d::Zero());
  EXPECT_NEAR((f - scene.ToolForce_W_N()).norm(), 0.0, 1e-9);
}

TEST(TissueBlock, ForceModelStiffnessBoundsTheStaticTangentStiffness) {
  // Reference: dF/d(depth) of the settled press, by a 0.1 mm finite
  // difference. The estimate treats the four contact nodes as uncoupled
  // springs, so it may only overestimate, and (measured) by less than 2x.
  auto settle = [](double depth_m) {
    auto scene = std::make_unique<TissueBlockScene>(TissueBlockParams{});
    Hold(*scene, ToolAt(0.0011, -0.0007, -depth_m), 0.8);
    return scene;
  };
  for (const double depth_m : {0.001, 0.003, 0.005}) {
    const auto a = settle(depth_m), b = settle(depth_m + 1e-4);
    const double tangent_N_per_m = (b->ToolForce_W_N().z() - a->ToolForce_W_N().z()) / 1e-4;
    const double contact_k = a->Params().contact_stiffness_N_per_m;
    // The tool-side reference includes the penalty spring in series, as the model does.
    EXPECT_GE(a->ForceModel().stiffness_N_per_m, tangent_N_per_m) << depth_m;
    EXPECT_LE(a->ForceModel().stiffness_N_per_m, 2.0 * tangent_N_per_m) << depth_m;
    EXPECT_LT(a->ForceModel().stiffness_N_per_m, contact_k);
  }
}

TEST(TissueBlock, ContactBeginAndEndAreLogged) {
  TissueBlockScene scene(TissueBlockParams{});
  // Down from 2 mm above to 2 mm deep and back at 20 mm/s, as a hand would.
  for (int k = 0; k <= 200; ++k) scene.Step(ToolAt(0, 0, 0.002 - 2e-5 * k), kTick_s);
  for (int k = 0; k <= 200; ++k) scene.Step(ToolAt(0, 0, -0.002 + 2e-5 * k), kTick_s);
  ASSERT_EQ(scene.Events().size(), 2u);
  EXPECT_EQ(scene.Events()[0].kind, SceneEventKind::kContactBegin);
  EXPECT_EQ(scene.Events()[1].kind, SceneEventKind::kContactEnd);
  EXPECT_EQ(scene.EventsTotal(), 2u);
}

TEST(TissueBlock, ReleaseReturnsTheSurfaceToRest) {
  TissueBlockScene scene(TissueBlockParams{});
  const Eigen::Matrix3Xd x0 = scene.Vertices_m();
  Hold(scene, ToolAt(0, 0, -0.006), 0.3);
  ASSERT_GT((scene.Vertices_m() - x0).cwiseAbs().maxCoeff(), 1e-3);
  Hold(scene, ToolAt(0, 0, 0.02), 1.0);
  // Anchored and damped: after 1 s the residual is far below a micrometre.
  EXPECT_LT((scene.Vertices_m() - x0).cwiseAbs().maxCoeff(), 1e-6);
  EXPECT_EQ(scene.ToolForce_W_N().norm(), 0.0);
}

TEST(TissueBlock, AbsurdToolInputsNeverBlowUp) {
  TissueBlockScene scene(TissueBlockParams{});
  const double inf = std::numeric_limits<double>::infinity();
  for (const ToolInput& t : {ToolAt(1e300, -1e300, -1e300), ToolAt(0, 0, -1e9), ToolAt(inf, 0, 0),
                             ToolAt(std::nan(""), 0, -0.01), ToolAt(0.029, 0.029, -0.5)}) {
    Hold(scene, t, 0.1);
    EXPECT_TRUE(scene.Vertices_m().allFinite());
    EXPECT_TRUE(scene.ToolForce_W_N().allFinite());
  }
  scene.Step(ToolAt(0, 0, -0.001), std::nan(""));
  scene.Step(ToolAt(0, 0, -0.001), -1.0);
  scene.Step(ToolAt(0, 0, -0.001), 1e6);  // truncated to the sub-step cap
  EXPECT_TRUE(scene.Vertices_m().allFinite());
  EXPECT_EQ(scene.Status().numerical_resets, 0u);
}

TEST(TissueBlock, BlowUpIsCountedAndTheSceneResetsItself) {
  // A guard bound far below what a press produces stands in for a blow-up.
  TissueBlockParams p;
  p.max_kinetic_energy_J = 1e-12;
  TissueBlockScene scene(p);
  Hold(scene, ToolAt(0, 0, -0.004), 0.05);
  EXPECT_GT(scene.Status().numerical_resets, 0u);
  EXPECT_EQ(scene.Status().numerical_resets, scene.State().blowups);
  bool reset_logged = false;
  for (const SceneEvent& e : scene.Events()) reset_logged = reset_logged || e.kind == SceneEventKind::kReset;
  EXPECT_TRUE(reset_logged);
  EXPECT_TRUE(scene.Vertices_m().allFinite());
  // After each reset the surface restarts from rest: it never sinks far.
  EXPECT_GT(scene.Vertices_m().row(2).minCoeff(), -0.004);
}

TEST(TissueBlock, EveryIntegratorGivesTheSameStaticPressForce) {
  // Statics do not depend on the integrator: all settle to one equilibrium.
  TissueBlockParams ref_params;
  TissueBlockScene ref(ref_params);
  const ToolInput tool = ToolAt(0.001, 0.001, -0.004);
  Hold(ref, tool, 1.0);
  for (int code : {0, 2, 3, 4, 5}) {
    TissueBlockParams p;
    p.integrator.kind = static_cast<IntegratorKind>(code);
    p.dt_s = 1e-4;  // below every explicit scheme's critical step here
    TissueBlockScene scene(p);
    Hold(scene, tool, 1.0);
    EXPECT_NEAR(scene.ToolForce_W_N().z(), ref.ToolForce_W_N().z(), 1e-6 * ref.ToolForce_W_N().z())
        << ToString(p.integrator.kind);
  }
}

TEST(TissueBlock, LocalUpdateRegionReproducesThePressForce) {
  // Gingival paper: update only near the contact. 6 hops around the contact
  // must give the full update's force within 1 %.
  const ToolInput tool = ToolAt(0.0011, -0.0007, -0.004);
  TissueBlockScene full(TissueBlockParams{});
  TissueBlockParams p;
  p.local_update_hops = 6;
  TissueBlockScene local(p);
  Hold(full, tool, 0.5);
  Hold(local, tool, 0.5);
  EXPECT_NEAR(local.ToolForce_W_N().z(), full.ToolForce_W_N().z(), 0.01 * full.ToolForce_W_N().z());
  // Released, the whole patch relaxes again (full update out of contact).
  Hold(local, ToolAt(0, 0, 0.02), 1.0);
  EXPECT_LT((local.Vertices_m() - local.Model().x0_m).cwiseAbs().maxCoeff(), 1e-6);
}

TEST(TissueBlock, SameInputsGiveBitIdenticalState) {
  auto run = [] {
    TissueBlockScene scene(TissueBlockParams{});
    for (int k = 0; k < 400; ++k)
      scene.Step(ToolAt(0.01 * std::sin(k * 0.01), 0.003, -0.004 * std::sin(k * 0.02)), kTick_s);
    return StateHash(scene.State());
  };
  EXPECT_EQ(run(), run());
}

TEST(TissueBlock, StepAllocatesNoMemory) {
  for (int code = 0; code <= 5; ++code) {
    TissueBlockParams p;
    p.integrator.kind = static_cast<IntegratorKind>(code);
    p.dt_s = 1e-4;  // sub-stepped: also covers the sub-step loop
    p.local_update_hops = code % 2 == 0 ? 3 : 0;  // and the local update path
    TissueBlockScene scene(p);
    scene.Step(ToolAt(0, 0, -0.003), kTick_s);  // warm up
    hapsim::test::ScopedAllocationCount allocations;
    for (int k = 0; k < 50; ++k) {
      scene.Step(ToolAt(0.0005 * k, 0, -0.003), kTick_s);
      (void)scene.ForceModel();
    }
    scene.Step(ToolAt(0, 0, 0.01), kTick_s);  // contact end event
    scene.Reset();
    EXPECT_EQ(allocations.Count(), 0u) << ToString(p.integrator.kind);
  }
}

}  // namespace
}  // namespace hapsim::core
