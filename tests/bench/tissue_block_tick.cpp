// One tissue_block scene tick through a class's press cycles, with the block
// sleeping out of contact (the default) and with the full step every tick,
// side by side. Command and figures: docs/performance.md#tissue_block-sleeps.
#include <benchmark/benchmark.h>

#include <algorithm>
#include <cmath>
#include <memory>
#include <vector>

#include "hapsim/core/scenes/tissue_block/tissue_block.h"

namespace {

using namespace hapsim::core;

// hapsim-load's `insertion` script: from 10 mm above the surface down at
// 10 mm/s to 5 mm deep, held 0.5 s, back up at 10 mm/s; the cycle repeats.
// Args: rest_displacement_m x 1e9 (0: the full step every tick; 100: the
// default), and the number of blocks (sessions) stepped one after the other
// in each iteration, their cycles 0.25 s apart. Time per iteration / blocks
// = time per session-tick (counter us_per_session_tick).
void BM_TissueBlockTick_InsertionCycle(benchmark::State& state) {
  TissueBlockParams p;
  p.rest_displacement_m = 1e-9 * static_cast<double>(state.range(0));
  const auto blocks = static_cast<int>(state.range(1));
  std::vector<std::unique_ptr<TissueBlockScene>> scenes;
  for (int b = 0; b < blocks; ++b) scenes.push_back(std::make_unique<TissueBlockScene>(p));
  constexpr double kSpeed_m_per_s = 10e-3, kAbove_m = 10e-3, kDepth_m = 5e-3, kHold_s = 0.5;
  constexpr double kDown_s = (kAbove_m + kDepth_m) / kSpeed_m_per_s, kCycle_s = 2.0 * kDown_s + kHold_s;
  ToolInput tool;
  tool.valid = true;
  long tick = 0, asleep = 0;
  for (auto _ : state) {
    for (int b = 0; b < blocks; ++b) {
      TissueBlockScene& s = *scenes[static_cast<std::size_t>(b)];
      const double t_s = std::fmod(1e-3 * static_cast<double>(tick) + 0.25 * b, kCycle_s);
      const double below_start_m = kSpeed_m_per_s * std::min({t_s, kDown_s, kCycle_s - t_s});
      tool.tip_W_m = Eigen::Vector3d(1.1e-3, -0.7e-3, kAbove_m - below_start_m);
      s.Step(tool, 1e-3);
      asleep += s.Asleep() ? 1 : 0;
      benchmark::DoNotOptimize(s.ToolForce_W_N());
    }
    ++tick;
  }
  const double session_ticks = static_cast<double>(std::max(tick, 1L) * blocks);
  state.counters["asleep_pct"] = 100.0 * static_cast<double>(asleep) / session_ticks;
  state.counters["us_per_session_tick"] = benchmark::Counter(
      static_cast<double>(blocks) * 1e-6, benchmark::Counter::kIsIterationInvariantRate | benchmark::Counter::kInvert);
}
// 7 000 iterations: two whole cycles.
BENCHMARK(BM_TissueBlockTick_InsertionCycle)
    ->ArgsProduct({{0, 100}, {1, 16}})
    ->Iterations(7000)
    ->Unit(benchmark::kMicrosecond);

}  // namespace

BENCHMARK_MAIN();
