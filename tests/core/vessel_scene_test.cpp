// The vessel scene: every shape builds at its defaults, a probe pressing the
// top of the straight vein is pushed back up and dents the wall, the wall
// leans on its bed, and bad parameters, bad poses and blow-ups are handled.
#include <cmath>
#include <cstdio>

#include <gtest/gtest.h>

#include "core/allocation_counter.h"
#include "hapsim/core/scenes/scene.h"
#include "hapsim/core/scenes/vessel/vessel_scene.h"
#include "core/scene_tick.h"

namespace hapsim::core {
namespace {

ToolInput TipAt(double x, double y, double z) {
  ToolInput t;
  t.valid = true;
  t.tip_W_m = Eigen::Vector3d(x, y, z);
  return t;
}

TEST(VesselScene, EveryShapeBuildsAtItsDefaultsWithinTheNodeLimit) {
  for (const int shape : {0, 1, 2}) {
    VesselScene scene(ParseVesselParams({{"shape", shape}}));
    EXPECT_LE(scene.Model().n, VesselLimits::kMaxNodes) << shape;
    EXPECT_GE(scene.Model().fewest_neighbours, 6) << shape;
    scene.Step(ToolInput{}, kTick_s);  // no tool: nothing moves from rest
    EXPECT_LT((scene.Nodes_m() - scene.Geometry().nodes_m).cwiseAbs().maxCoeff(), 1e-12) << shape;
    std::printf("shape %d: %d nodes, %ld surface vertices, fewest neighbours %d, mass scale %.0f\n", shape,
                scene.Model().n, static_cast<long>(scene.Vertices_m().cols()), scene.Model().fewest_neighbours,
                scene.MassScale());
  }
}

TEST(VesselScene, APressOnTheTopPushesTheProbeUpAndDentsTheWall) {
  VesselScene scene(VesselParams{});
  const double probe = scene.Params().probe_radius_m;
  // Straight down onto the crest at x = 0.3 mm (off a node), 5 mm/s, to 1 mm
  // below first touch; the crest is at z = 0.
  double last_force = 0.0;
  int rising = 0, samples = 0;
  for (int k = 0; k <= 400; ++k) {
    const double z = probe + 1e-3 - 5e-6 * k;
    scene.Step(TipAt(3e-4, 0.0, z), kTick_s);
    const Eigen::Vector3d f = scene.ToolForce_W_N();
    if (k % 40 == 0 && z < probe - 1e-4) {
      ++samples;
      if (f.z() > last_force) ++rising;
      last_force = f.z();
    }
  }
  const Eigen::Vector3d f = scene.ToolForce_W_N();
  std::printf("probe 1 mm into the vein's crest: force (%.4f, %.4f, %.4f) N, render stiffness %.1f N/m\n", f.x(),
              f.y(), f.z(), scene.ForceModel().stiffness_N_per_m);
  EXPECT_GT(f.z(), 0.0);
  EXPECT_LT(std::abs(f.y()), 0.2 * f.z());  // centred press: mostly vertical
  EXPECT_EQ(rising, samples);               // deeper, harder
  EXPECT_EQ(scene.ForceModel().state, ContactState::kContact);
  EXPECT_EQ(scene.Status().current_layer, 0);
  // The crest went down with the probe (a dent), and no node went through the bed.
  double crest_under_probe_m = -1.0;
  for (Eigen::Index i = 0; i < scene.Nodes_m().cols(); ++i) {
    const Eigen::Vector3d x = scene.Nodes_m().col(i);
    if (std::abs(x.x() - 3e-4) < 5e-4 && std::abs(x.y()) < 5e-4) crest_under_probe_m = std::max(crest_under_probe_m, x.z());
  }
  EXPECT_LT(crest_under_probe_m, -5e-4);  // the sphere's bottom is 1 mm below the crest's rest height
  EXPECT_GE(scene.Nodes_m().row(2).minCoeff(), scene.Geometry().nodes_m.row(2).minCoeff() - 1e-12);
}

TEST(VesselScene, AnUnstableStepIsRefusedNamingTheParameters) {
  try {
    VesselScene scene(ParseVesselParams({{"mass_scale", 1.0}, {"substeps", 1}}));
    FAIL() << "accepted";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("raise 'substeps' or 'mass_scale'"), std::string::npos) << e.what();
  }
}

TEST(VesselScene, TooManyNodesAreRefusedBeforeBuilding) {
  EXPECT_THROW(ParseVesselParams({{"node_spacing_m", 1e-4}}), std::invalid_argument);
}

TEST(VesselScene, ANonFiniteOrFarAwayToolIsAbsentNotACrash) {
  VesselScene scene(VesselParams{});
  for (const ToolInput& t : {TipAt(NAN, 0, 0), TipAt(0, 0, 1e9), TipAt(0, INFINITY, 0)}) {
    scene.Step(t, kTick_s);
    EXPECT_EQ(scene.ToolForce_W_N(), Eigen::Vector3d::Zero());
    EXPECT_EQ(scene.ForceModel().state, ContactState::kFree);
  }
  EXPECT_EQ(scene.Status().numerical_resets, 0u);
}

TEST(VesselScene, ABlowUpIsCountedAndTheSceneResetsItself) {
  // Any motion exceeds a kinetic-energy limit of 1e-30 J: the guard fires.
  VesselScene scene(ParseVesselParams({{"max_kinetic_energy_J", 1e-30}}));
  for (int k = 0; k < 50; ++k) scene.Step(TipAt(0, 0, 5e-4 - 1e-5 * k), kTick_s);
  EXPECT_GT(scene.Status().numerical_resets, 0u);
  EXPECT_TRUE(scene.Nodes_m().allFinite());
}

}  // namespace
}  // namespace hapsim::core

namespace hapsim::core {
namespace {

// The paper's two baselines on the same nodes, and the paper's model with its
// tetrahedron energy constraints on (3): each pushes a pressing probe back,
// and none allocates in a tick.
class VesselBaselines : public ::testing::TestWithParam<int> {};

TEST_P(VesselBaselines, APressPushesBackAndTicksAllocateNothing) {
  VesselParams params;
  params.model = GetParam() == 3 ? 0 : GetParam();
  if (GetParam() == 3) params.tet_fraction = 0.2;
  VesselScene scene(params);
  scene.Step(ToolInput{}, kTick_s);
  std::uint64_t allocations = 0;
  {
    hapsim::test::ScopedAllocationCount count;
    for (int k = 0; k <= 400; ++k) scene.Step(TipAt(3e-4, 0.0, params.probe_radius_m + 1e-3 - 5e-6 * k), kTick_s);
    allocations = count.Count();
  }
  EXPECT_EQ(allocations, 0u);
  EXPECT_GT(scene.ToolForce_W_N().z(), 0.0);
  EXPECT_EQ(scene.Status().numerical_resets, 0u);
  std::printf("model %d: 1 mm past first touch, force %.4f N\n", GetParam(), scene.ToolForce_W_N().z());
}

INSTANTIATE_TEST_SUITE_P(Models, VesselBaselines, ::testing::Values(1, 2, 3));

}  // namespace
}  // namespace hapsim::core
