// Local update region (gingival paper): integrate only near the contact.
// With every node in the region it must be the full update, bit for bit;
// frozen nodes must not move; the error against the full update must shrink
// as the region grows.
#include "hapsim/core/msm/local_region.h"

#include <gtest/gtest.h>

#include "hapsim/core/msm/msm_step.h"
#include "hapsim/core/scenes/tissue_block/tissue_block.h"

namespace hapsim::core {
namespace {

MsmModel Patch() {
  TissueBlockParams p;
  p.grid_nodes = 31;
  return BuildMsmModel(MakeTissueGridDef(p));
}

constexpr std::int32_t kCentre = 15 * 31 + 15;
constexpr IntegratorChoice kRegionSymplectic{IntegratorKind::kSymplecticEuler, 0.5};

// Press the centre node with 0.5 N for 100 ms, full or local.
MsmState Press(const MsmModel& model, const LocalRegion* region, IntegratorChoice method = kRegionSymplectic) {
  MsmState state = MakeMsmState(model);
  MsmWorkspace ws = MakeMsmWorkspace(model);
  state.f_ext_N(2, kCentre) = -0.5;
  for (int k = 0; k < 100; ++k) {
    if (region) {
      StepMsmLocal(model, state, 1e-3, method, ws, *region);
    } else {
      StepMsm(model, state, 1e-3, method, ws);
    }
  }
  return state;
}

TEST(LocalRegion, RegionOfAllNodesIsTheFullUpdateBitForBit) {
  const MsmModel model = Patch();
  LocalRegion region = MakeLocalRegion(model);
  SelectAllNodes(model, region);
  for (int kind = 0; kind < kNumIntegratorKinds; ++kind) {
    const IntegratorChoice method{static_cast<IntegratorKind>(kind), 0.375};
    if (method.kind == IntegratorKind::kExplicitEuler) continue;  // unstable at 1 ms here
    EXPECT_EQ(StateHash(Press(model, &region, method)), StateHash(Press(model, nullptr, method)))
        << ToString(method.kind);
  }
}

TEST(LocalRegion, HopsSelectTheGraphNeighbourhoodAndFrozenNodesStayPut) {
  const MsmModel model = Patch();
  LocalRegion region = MakeLocalRegion(model);
  SelectLocalRegion(model, kCentre, 2, region);
  // Structural + shear springs: 2 hops on the grid = the 5 x 5 block.
  EXPECT_EQ(region.active_nodes.size(), 25u);
  const MsmState pressed = Press(model, &region);
  std::vector<bool> active(static_cast<std::size_t>(model.num_nodes), false);
  for (std::int32_t i : region.active_nodes) active[static_cast<std::size_t>(i)] = true;
  for (std::int32_t i = 0; i < model.num_nodes; ++i) {
    if (!active[static_cast<std::size_t>(i)]) {
      EXPECT_EQ(pressed.x_m.col(i), model.x0_m.col(i)) << i;
    }
  }
  EXPECT_LT(pressed.x_m(2, kCentre), -1e-3);
}

TEST(LocalRegion, ErrorAgainstFullUpdateShrinksAsTheRegionGrows) {
  const MsmModel model = Patch();
  const MsmState full = Press(model, nullptr);
  LocalRegion region = MakeLocalRegion(model);
  double previous_m = INFINITY;
  for (const std::int32_t hops : {1, 2, 4, 8}) {
    SelectLocalRegion(model, kCentre, hops, region);
    const double error_m = (Press(model, &region).x_m - full.x_m).cwiseAbs().maxCoeff();
    EXPECT_LT(error_m, previous_m) << hops << " hops";
    previous_m = error_m;
  }
  // 8 hops: within 1 % of the centre deflection.
  EXPECT_LT(previous_m, 0.01 * std::abs(full.x_m(2, kCentre)));
}

// A bad seed is a programming error reachable from a step: it aborts with a
// message (HAPSIM_DEMAND), it does not throw through Step().
TEST(LocalRegionDeathTest, BadSeedAbortsWithAMessage) {
  const MsmModel model = Patch();
  LocalRegion region = MakeLocalRegion(model);
  EXPECT_DEATH(SelectLocalRegion(model, -1, 2, region), "HAPSIM_DEMAND failed.*seed node out of");
  EXPECT_DEATH(SelectLocalRegion(model, model.num_nodes, 2, region), "seed node out of");
}

}  // namespace
}  // namespace hapsim::core
