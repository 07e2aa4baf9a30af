// The AVX-512 spring kernel and node pass against the portable kernel, bit
// for bit: for every integrator, on the full and the local update, after
// cutting edits and on a mesh whose springs come in random order (where
// consecutive springs share nodes and the scatter order matters).
#include "hapsim/core/msm/spring_kernel.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cstring>
#include <numeric>
#include <random>
#include <string>
#include <vector>

#include "hapsim/core/msm/msm_step.h"
#include "hapsim/core/msm/local_region.h"
#include "hapsim/core/msm/msm_topology.h"
#include "hapsim/core/scenes/tissue_block/tissue_block.h"
#include "msm_test_models.h"

namespace hapsim::core {
namespace {

using test::kAllMethods;
using test::Name;

// Skips the calling test on a CPU without AVX-512 (the portable kernel is
// then the only one, and the comparison would be with itself).
#define REQUIRE_AVX512()                                                          \
  if (!SpringKernelSupported(SpringKernel::kAvx512)) {                            \
    GTEST_SKIP() << "this CPU has no AVX-512F/VL: only the portable kernel runs"; \
  }

// A 40 x 40 tissue grid (~6,000 springs) with every node displaced, so no
// spring is at rest.
MsmDef DisturbedGridDef() {
  TissueBlockParams p;
  p.grid_nodes = 40;
  p.size_m = 0.003 * (p.grid_nodes - 1);
  MsmDef def = MakeTissueGridDef(p);
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> jitter(-2e-4, 2e-4);
  for (Eigen::Index i = 0; i < def.x0_m.size(); ++i) def.x0_m.data()[i] += jitter(rng);
  def.spring_capacity = static_cast<std::int32_t>(def.springs.size()) + 16;
  def.max_node_degree = 12;  // room for the cut's added spring
  return def;
}

// The same springs in random order.
MsmDef Shuffled(const MsmDef& def) {
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
  return shuffled;
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
// `cut` is set (the same edits for both kernels).
SimRun Simulate(MsmModel model, IntegratorChoice method, SpringKernel kernel, bool cut) {
  SimRun run{StartState(model), {}};
  MsmWorkspace ws = MakeMsmWorkspace(model);
  ws.spring_kernel = kernel;
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

TEST(SpringKernel, PortableIsAlwaysSupportedAndTheWorkspaceTakesTheBest) {
  EXPECT_TRUE(SpringKernelSupported(SpringKernel::kPortable));
  EXPECT_STREQ(SpringKernelName(SpringKernel::kPortable), "portable");
  EXPECT_STREQ(SpringKernelName(SpringKernel::kAvx512), "avx512");
  EXPECT_TRUE(SpringKernelSupported(BestSpringKernel()));
  EXPECT_EQ(MakeMsmWorkspace(BuildMsmModel(DisturbedGridDef())).spring_kernel, BestSpringKernel());
}

TEST(SpringKernel, Avx512MatchesPortableBitForBitForEveryIntegrator) {
  REQUIRE_AVX512();
  const MsmModel model = BuildMsmModel(DisturbedGridDef());
  for (const IntegratorChoice method : kAllMethods) {
    for (const bool cut : {false, true}) {
      const SimRun reference = Simulate(model, method, SpringKernel::kPortable, cut);
      ASSERT_TRUE(reference.state.x_m.allFinite());
      // The steps moved the nodes (the comparison is not between two rests).
      EXPECT_GT((reference.state.x_m - model.x0_m).cwiseAbs().maxCoeff(), 1e-6);
      ExpectBitIdentical(reference, Simulate(model, method, SpringKernel::kAvx512, cut),
                         Name(method) + (cut ? ", with cuts" : ""));
    }
  }
}

TEST(SpringKernel, Avx512MatchesPortableWithSpringsInRandomOrder) {
  REQUIRE_AVX512();
  const MsmModel model = BuildMsmModel(Shuffled(DisturbedGridDef()));
  for (const IntegratorChoice method : kAllMethods)
    ExpectBitIdentical(Simulate(model, method, SpringKernel::kPortable, false),
                       Simulate(model, method, SpringKernel::kAvx512, false),
                       Name(method) + ", shuffled springs");
}

TEST(SpringKernel, Avx512MatchesPortableOnTheLocalUpdate) {
  REQUIRE_AVX512();
  const MsmModel model = BuildMsmModel(DisturbedGridDef());
  LocalRegion region = MakeLocalRegion(model);
  SelectLocalRegion(model, 820, 4, region);
  ASSERT_GT(region.springs.size(), 40u);
  for (const IntegratorChoice method : kAllMethods) {
    std::vector<std::uint64_t> hashes;
    for (const SpringKernel kernel : {SpringKernel::kPortable, SpringKernel::kAvx512}) {
      MsmState state = StartState(model);
      MsmWorkspace ws = MakeMsmWorkspace(model);
      ws.spring_kernel = kernel;
      for (int k = 0; k < 30; ++k) {
        state.f_ext_N(2, 820) = -0.2;
        StepMsmLocal(model, state, 1e-4, method, ws, region);
      }
      hashes.push_back(StateHash(state));
    }
    EXPECT_EQ(hashes[0], hashes[1]) << Name(method);
  }
}

}  // namespace
}  // namespace hapsim::core
