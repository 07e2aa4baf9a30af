// The fast paths of the MSM step against the reference path, bit for bit:
// the AVX-512 spring kernel and node pass against the portable kernel, and
// the fused sweep (springs and nodes chunk by chunk) against a spring pass
// followed by a node pass — for every integrator, on the full and the local
// update, after cutting edits, and on a mesh whose springs are shuffled
// (where the fused sweep must still wait for each node's last spring).
#include "hapsim/core/msm/spring_kernel.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cstring>
#include <numeric>
#include <random>
#include <string>
#include <vector>

#include "hapsim/core/integrators/msm_step.h"
#include "hapsim/core/msm/local_region.h"
#include "hapsim/core/msm/msm_topology.h"
#include "hapsim/core/scenes/tissue_block.h"

namespace hapsim::core {
namespace {

struct PathChoice {
  SpringKernel kernel;
  bool fused;
  std::string Name() const { return std::string(SpringKernelName(kernel)) + (fused ? " fused" : " two-pass"); }
};

// Every kernel this CPU runs, each with and without the fused sweep.
std::vector<PathChoice> FastPaths() {
  std::vector<PathChoice> paths = {{SpringKernel::kPortable, true}};
  if (SpringKernelSupported(SpringKernel::kAvx512)) {
    paths.push_back({SpringKernel::kAvx512, false});
    paths.push_back({SpringKernel::kAvx512, true});
  }
  return paths;
}
const PathChoice kReference{SpringKernel::kPortable, false};

constexpr IntegratorChoice kAllMethods[] = {
    {IntegratorKind::kExplicitEuler, 0.5},     {IntegratorKind::kSymplecticEuler, 0.5},
    {IntegratorKind::kImprovedEuler, 0.5},     {IntegratorKind::kMidpointAveraging, 0.375},
    {IntegratorKind::kRk4, 0.5},               {IntegratorKind::kBackwardEuler, 0.5},
};

// A 40 x 40 tissue grid (~6,000 springs: several fused chunks) with every
// node displaced and moving, so no spring is at rest.
MsmDef DisturbedGridDef() {
  TissueBlockParams p;
  p.grid_nodes = 40;
  p.size_m = 0.003 * (p.grid_nodes - 1);
  MsmDef def = MakeTissueGridDef(p);
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> jitter(-2e-4, 2e-4);
  for (Eigen::Index i = 0; i < def.x0_m.size(); ++i) def.x0_m.data()[i] += jitter(rng);
  def.spring_capacity = static_cast<std::int32_t>(def.springs.size()) + 16;
  return def;
}

MsmState StartState(const MsmModel& model) {
  MsmState state = MakeMsmState(model);
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> speed(-0.05, 0.05);
  for (Eigen::Index i = 0; i < state.v_m_per_s.size(); ++i) state.v_m_per_s.data()[i] = speed(rng);
  return state;
}

struct SimRun {
  MsmState state;
  std::vector<double> kinetic_energy_J;
};

// 40 steps with a moving press; cuts two springs and adds one halfway when
// `cut` is set (the same edits on every path).
SimRun Simulate(MsmModel model, IntegratorChoice method, PathChoice path, bool cut) {
  SimRun run{StartState(model), {}};
  MsmWorkspace ws = MakeMsmWorkspace(model);
  ws.spring_kernel = path.kernel;
  ws.fused_sweep = path.fused;
  for (int k = 0; k < 40; ++k) {
    if (cut && k == 20) {
      RemoveSpring(model, 100);
      RemoveSpring(model, 2000);
      AddSpring(model, 5, 1234, 0.01, 40.0, 0.01);
    }
    run.state.f_ext_N(2, 820) = -0.2 * std::sin(0.3 * k);
    run.kinetic_energy_J.push_back(StepMsm(model, run.state, 1e-4, method, ws).kinetic_energy_J);
  }
  return run;
}

void ExpectBitIdentical(const SimRun& a, const SimRun& b, const std::string& what) {
  ASSERT_EQ(a.state.x_m.size(), b.state.x_m.size());
  EXPECT_EQ(0, std::memcmp(a.state.x_m.data(), b.state.x_m.data(), sizeof(double) * a.state.x_m.size())) << what;
  EXPECT_EQ(0, std::memcmp(a.state.v_m_per_s.data(), b.state.v_m_per_s.data(),
                           sizeof(double) * a.state.v_m_per_s.size()))
      << what;
  EXPECT_EQ(a.kinetic_energy_J, b.kinetic_energy_J) << what;  // exact double equality
}

TEST(SpringKernel, PortableIsAlwaysSupportedAndNamesAreStable) {
  EXPECT_TRUE(SpringKernelSupported(SpringKernel::kPortable));
  EXPECT_STREQ(SpringKernelName(SpringKernel::kPortable), "portable");
  EXPECT_STREQ(SpringKernelName(SpringKernel::kAvx512), "avx512");
  EXPECT_TRUE(SpringKernelSupported(BestSpringKernel()));
  EXPECT_EQ(MakeMsmWorkspace(BuildMsmModel(DisturbedGridDef())).spring_kernel, BestSpringKernel());
}

TEST(SpringKernel, EveryFastPathMatchesTheReferenceBitForBit) {
  const MsmModel model = BuildMsmModel(DisturbedGridDef());
  ASSERT_GT(model.NumSprings(), 4 * kFusedChunkSprings);
  for (const IntegratorChoice method : kAllMethods) {
    for (const bool cut : {false, true}) {
      const SimRun reference = Simulate(model, method, kReference, cut);
      ASSERT_TRUE(reference.state.x_m.allFinite());
      // The steps moved the nodes (the comparison is not between two rests).
      EXPECT_GT((reference.state.x_m - model.x0_m).cwiseAbs().maxCoeff(), 1e-6);
      for (const PathChoice path : FastPaths())
        ExpectBitIdentical(reference, Simulate(model, method, path, cut),
                           std::string(ToString(method.kind)) + ", " + path.Name() + (cut ? ", with cuts" : ""));
    }
  }
}

TEST(SpringKernel, FusedSweepWaitsForEachNodesLastSpringInAnyOrder) {
  // Springs in random order: a node's last spring can come anywhere, so
  // the sweep must hold nodes back until it has run.
  MsmDef def = DisturbedGridDef();
  std::vector<std::size_t> order(def.springs.size());
  std::iota(order.begin(), order.end(), 0);
  std::shuffle(order.begin(), order.end(), std::mt19937(3));
  MsmDef shuffled = def;
  for (std::size_t k = 0; k < order.size(); ++k) {
    shuffled.springs[k] = def.springs[order[k]];
    shuffled.spring_rest_m[k] = def.spring_rest_m[order[k]];
    shuffled.spring_k_N_per_m[k] = def.spring_k_N_per_m[order[k]];
    shuffled.spring_c_Ns_per_m[k] = def.spring_c_Ns_per_m[order[k]];
  }
  const MsmModel model = BuildMsmModel(shuffled);
  for (const IntegratorChoice method : kAllMethods) {
    const SimRun reference = Simulate(model, method, kReference, false);
    for (const PathChoice path : FastPaths())
      ExpectBitIdentical(reference, Simulate(model, method, path, false),
                         std::string(ToString(method.kind)) + ", shuffled springs, " + path.Name());
  }
}

TEST(SpringKernel, FusedScheduleNeverReleasesANodeALaterSpringTouches) {
  for (const bool shuffle : {false, true}) {
    MsmDef def = DisturbedGridDef();
    if (shuffle) std::shuffle(def.springs.begin(), def.springs.end(), std::mt19937(5));
    const MsmModel model = BuildMsmModel(def);
    MsmState state = MakeMsmState(model);
    MsmWorkspace ws = MakeMsmWorkspace(model);
    StepMsm(model, state, 1e-4, {IntegratorKind::kSymplecticEuler, 0.5}, ws);  // builds the schedule
    ASSERT_EQ(ws.fused_num_springs, model.NumSprings());
    const std::int32_t chunks = (model.NumSprings() + kFusedChunkSprings - 1) / kFusedChunkSprings;
    std::int32_t released = 0;
    for (std::int32_t c = 0; c < chunks; ++c) {
      const std::int32_t end = ws.fused_node_end[static_cast<std::size_t>(c)];
      ASSERT_GE(end, released) << "chunk " << c;
      released = end;
      for (std::int32_t s = (c + 1) * kFusedChunkSprings; s < model.NumSprings(); ++s) {
        ASSERT_GE(model.spring_i[static_cast<std::size_t>(s)], released) << "chunk " << c << " spring " << s;
        ASSERT_GE(model.spring_j[static_cast<std::size_t>(s)], released) << "chunk " << c << " spring " << s;
      }
    }
    // Ordered grid: nodes are released row by row as the sweep goes; shuffled:
    // hardly any node is free before the last chunk.
    if (!shuffle) {
      EXPECT_GT(ws.fused_node_end[static_cast<std::size_t>(chunks / 2)], model.num_nodes / 3);
    }
  }
}

TEST(SpringKernel, LocalUpdateMatchesAcrossKernels) {
  const MsmModel model = BuildMsmModel(DisturbedGridDef());
  LocalRegion region = MakeLocalRegion(model);
  SelectLocalRegion(model, 820, 4, region);
  ASSERT_GT(region.springs.size(), 40u);
  for (const IntegratorChoice method : kAllMethods) {
    std::vector<MsmState> finals;
    for (const PathChoice path : {kReference, PathChoice{BestSpringKernel(), true}}) {
      MsmState state = StartState(model);
      MsmWorkspace ws = MakeMsmWorkspace(model);
      ws.spring_kernel = path.kernel;
      for (int k = 0; k < 30; ++k) {
        state.f_ext_N(2, 820) = -0.2;
        StepMsmLocal(model, state, 1e-4, method, ws, region);
      }
      finals.push_back(state);
    }
    EXPECT_EQ(StateHash(finals[0]), StateHash(finals[1])) << ToString(method.kind);
  }
}

}  // namespace
}  // namespace hapsim::core
