// Determinism golden test: a fixed tissue-grid
// scenario must end in the same state hash on every build, CPU and spring
// kernel. The hashes below were recorded when the AVX-512 kernel was added,
// and are also what the step gave before it (commit b1a99af, checked by
// building that commit). A change to them means the physics changed
// bit-wise: if that is intended, say why in the commit and record the new
// values.
//
// The inputs avoid libm functions other than sqrt (correctly rounded by
// IEEE 754), so the hash does not depend on the C library's sin/exp.
#include <gtest/gtest.h>

#include <cstdint>
#include <string>

#include "hapsim/core/msm/msm_step.h"
#include "hapsim/core/msm/spring_kernel.h"
#include "hapsim/core/scenes/tissue_block/tissue_block.h"

namespace hapsim::core {
namespace {

struct Golden {
  IntegratorChoice method;
  std::uint64_t hash;
};

// 200 steps of 0.1 ms on a 30 x 30 grid pressed off-centre with a force
// that ramps up and back down linearly.
std::uint64_t ScenarioHash(IntegratorChoice method, SpringKernel kernel) {
  TissueBlockParams p;
  p.grid_nodes = 30;
  p.size_m = 0.003 * (p.grid_nodes - 1);
  const MsmModel model = BuildMsmModel(MakeTissueGridDef(p));
  MsmState state = MakeMsmState(model);
  MsmWorkspace ws = MakeMsmWorkspace(model);
  ws.spring_kernel = kernel;
  const std::int32_t pressed = 11 * p.grid_nodes + 17;
  for (int k = 0; k < 200; ++k) {
    const double ramp = k < 100 ? k / 100.0 : (200 - k) / 100.0;
    state.f_ext_N(2, pressed) = -0.4 * ramp;
    state.f_ext_N(0, pressed) = 0.05 * ramp;
    StepMsm(model, state, 1e-4, method, ws);
  }
  return StateHash(state);
}

constexpr Golden kGolden[] = {
    {{IntegratorKind::kExplicitEuler, 0.5}, 4998424984311384686ull},
    {{IntegratorKind::kSymplecticEuler, 0.5}, 18062992685794254988ull},
    {{IntegratorKind::kImprovedEuler, 0.5}, 6981106071387765952ull},
    {{IntegratorKind::kMidpointAveraging, 0.375}, 12288480141893843197ull},
    {{IntegratorKind::kRk4, 0.5}, 1743071177130901841ull},
    {{IntegratorKind::kBackwardEuler, 0.5}, 4082540052709718194ull},
};

TEST(Determinism, TissueGridScenarioEndsInTheGoldenHashOnEveryPath) {
  for (const Golden& g : kGolden) {
    for (const SpringKernel kernel : {SpringKernel::kPortable, SpringKernel::kAvx512}) {
      if (!SpringKernelSupported(kernel)) continue;  // kPortable always runs
      EXPECT_EQ(ScenarioHash(g.method, kernel), g.hash)
          << std::hex << ToString(g.method.kind) << ", " << SpringKernelName(kernel);
    }
  }
}

}  // namespace
}  // namespace hapsim::core
