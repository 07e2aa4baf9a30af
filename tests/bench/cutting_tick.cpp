// One cutting scene tick while the blade cuts (grid rebuild + cylinder
// collision, contact, the progressive three-stage cut, residual stress, the
// MSM step), on ~10k- and ~100k-node skins; beside it, in the same run, the
// same skins with the blade in the air (the plain step: the baseline the cut
// adds to) and the blade collision alone, grid against brute force.
// Target: <= 1 ms per cutting tick at 10k nodes (1 kHz on one core).
// Run: build/bin/bench_cutting_tick (see docs/performance.md).
#include <time.h>

#include <algorithm>
#include <cmath>
#include <vector>

#include <benchmark/benchmark.h>

#include "hapsim/core/cutting/cylinder_collision.h"
#include "hapsim/core/scenes/cutting/cutting_scene.h"
#include "hapsim/core/spatial/uniform_grid.h"

namespace {

using namespace hapsim::core;

constexpr double kSpeed_m_per_s = 0.02;  // the validation's cutting speed
constexpr double kDepth_m = 0.0015;
constexpr double kStroke_m = 0.04;      // along x, centred on the 60 mm patch

double ThreadCpu_s() {
  timespec ts{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
  return static_cast<double>(ts.tv_sec) + 1e-9 * static_cast<double>(ts.tv_nsec);
}

// Grid spacing for a 60 x 40 mm patch of about `nodes` nodes; resting skin
// (the default) or every node every step (rest_force_N = 0).
CuttingParams SkinOf(int nodes, bool resting = true) {
  CuttingParams p;
  p.spacing_m = std::sqrt(p.patch_length_m * p.patch_width_m / nodes);
  if (!resting) p.rest_force_N = 0.0;
  return p;
}

ToolInput Blade(double x, double z, const Eigen::Vector3d& v) {
  ToolInput t;
  t.valid = true;
  t.tip_W_m = Eigen::Vector3d(x, 0.0003, z);
  t.orientation_W = Eigen::Quaterniond::FromTwoVectors(Eigen::Vector3d::UnitZ(), Eigen::Vector3d(-0.5, 0.0, std::sqrt(0.75)));
  t.velocity_W_m_per_s = v;
  return t;
}

// Resets the scene and presses the blade in at the stroke's start until it cuts.
void PressIn(CuttingScene& s) {
  s.Reset();
  const double x0 = -0.5 * kStroke_m;
  for (double z = 0.002; !s.Cutting() && z > -2.0 * kDepth_m; z -= kSpeed_m_per_s * 1e-3)
    s.Step(Blade(x0, z, {0, 0, -kSpeed_m_per_s}), 1e-3);
}

// Cutting ticks: the blade draws a 40 mm incision at 20 mm/s; at its end the
// scene is reset and the blade pressed in again (untimed). Counters, in
// thread CPU time (preemption on the shared VM does not count): the mean,
// 99th percentile and slowest tick, and the mean of the ticks that
// committed a segment of the cut (the cut's own cost is there).
void BM_CuttingTick_Cutting(benchmark::State& state) {
  CuttingScene s(SkinOf(static_cast<int>(state.range(0)), state.range(1) != 0));
  PressIn(s);
  const double step_m = kSpeed_m_per_s * 1e-3;
  double x = -0.5 * kStroke_m, commit_s = 0.0;
  std::vector<double> tick_s;
  tick_s.reserve(1 << 20);
  std::int64_t commits = 0;
  double awake_sum = 0.0;
  for (auto _ : state) {
    x += step_m;
    if (x > 0.5 * kStroke_m) {
      state.PauseTiming();
      PressIn(s);
      x = -0.5 * kStroke_m;
      state.ResumeTiming();
    }
    const std::uint32_t before = s.CutTotals().triangles_removed;
    const double t0 = ThreadCpu_s();
    s.Step(Blade(x, -kDepth_m, {kSpeed_m_per_s, 0, 0}), 1e-3);
    const double dt = ThreadCpu_s() - t0;
    if (tick_s.size() < tick_s.capacity()) tick_s.push_back(dt);
    if (s.CutTotals().triangles_removed != before) commit_s += dt, ++commits;
    benchmark::DoNotOptimize(s.ToolForce_W_N());
    awake_sum += s.AwakeNodes();
  }
  if (!s.Cutting()) state.SkipWithError("the blade stopped cutting");
  std::sort(tick_s.begin(), tick_s.end());
  double sum = 0.0;
  for (const double t : tick_s) sum += t;
  const auto n = static_cast<double>(std::max<std::size_t>(tick_s.size(), 1));
  state.counters["nodes"] = static_cast<double>(s.Skin().nx * s.Skin().ny);
  state.counters["mean_us"] = 1e6 * sum / n;
  state.counters["p99_us"] = tick_s.empty() ? 0.0 : 1e6 * tick_s[static_cast<std::size_t>(0.99 * (n - 1))];
  state.counters["max_us"] = tick_s.empty() ? 0.0 : 1e6 * tick_s.back();
  state.counters["commit_mean_us"] = commits ? 1e6 * commit_s / static_cast<double>(commits) : 0.0;
  state.counters["awake_nodes"] = awake_sum / static_cast<double>(std::max<std::int64_t>(state.iterations(), 1));
}
// Args: skin nodes (3876: the scene's default), resting skin (1) or the full step (0: the baseline).
BENCHMARK(BM_CuttingTick_Cutting)
    ->ArgsProduct({{3876, 10000, 100000}, {0, 1}})
    ->Unit(benchmark::kMicrosecond)
    ->MinTime(3.0);

// Baseline: the same skin, the blade held in the air (collision finds
// nothing, no cut): the MSM step of every node (resting skin would do
// nothing here).
void BM_CuttingTick_BladeInAir(benchmark::State& state) {
  CuttingScene s(SkinOf(static_cast<int>(state.range(0)), false));
  for (auto _ : state) {
    s.Step(Blade(0.0, 0.005, Eigen::Vector3d::Zero()), 1e-3);
    benchmark::DoNotOptimize(s.ToolForce_W_N());
  }
  state.counters["nodes"] = static_cast<double>(s.Skin().nx * s.Skin().ny);
}
BENCHMARK(BM_CuttingTick_BladeInAir)->Arg(10000)->Arg(100000)->Unit(benchmark::kMicrosecond);

// The blade's collision alone at cutting depth, three ways: the paper's
// test on every node (arg 0), a grid of the current positions rebuilt every
// tick (arg 1), and the scene's way: a grid of the rest positions built once
// per topology change, queried with the largest displacement from rest,
// found in one pass every tick (arg 2).
void BM_BladeCollision(benchmark::State& state) {
  CuttingScene s(SkinOf(static_cast<int>(state.range(0))));
  const int mode = static_cast<int>(state.range(1));
  const Cylinder blade = s.BladeOf(Blade(0.0, -kDepth_m, Eigen::Vector3d::Zero()));
  const auto& skin = s.Skin();
  UniformGrid grid(Eigen::AlignedBox3d(Eigen::Vector3d(-0.04, -0.03, -0.005), Eigen::Vector3d(0.04, 0.03, 0.005)),
                   std::max(2.0 * blade.radius_m, 2.0 * skin.def.spacing_m), static_cast<std::size_t>(skin.model.num_nodes));
  if (mode == 2) grid.Build(skin.model.x0_m, skin.model.node_live);
  std::vector<std::uint32_t> hits;
  hits.reserve(static_cast<std::size_t>(skin.model.num_nodes));
  for (auto _ : state) {
    if (mode == 0) {
      CollideBruteForce(blade, skin.state.x_m, skin.model.node_live, hits);
    } else if (mode == 1) {
      grid.Build(skin.state.x_m, skin.model.node_live);
      CollideWithGrid(blade, skin.state.x_m, grid, hits);
    } else {
      const double shift = MaxDisplacement_m(skin.state.x_m, skin.model.x0_m, skin.model.node_live, skin.state.x_m.cols());
      CollideWithShiftedGrid(blade, skin.state.x_m, grid, shift, hits);
    }
    benchmark::DoNotOptimize(hits.data());
  }
  state.counters["hits"] = static_cast<double>(hits.size());
}
BENCHMARK(BM_BladeCollision)->ArgsProduct({{10000, 100000}, {0, 1, 2}})->Unit(benchmark::kMicrosecond);

}  // namespace

BENCHMARK_MAIN();
