// One MSM step (spring forces + integration + stability guard) on tissue
// grids from ~1k to ~1M springs, single thread, against a STREAM-style
// triad over arrays of the same total size measured in the same run.
//
// Counters per mesh:
//   springs_per_s   spring updates per second (springs x steps / CPU time;
//                   multi-stage schemes evaluate each spring several times)
//   step_GBps       compulsory bytes of one step (model below) / time
//   triad_GBps      a[i] = b[i] + s c[i] over 3 arrays whose total size equals
//                   the step's working set, STREAM byte counting (24 B/elem)
//   bw_fraction     step_GBps / triad_GBps: 1 = as fast as memory allows
//                   (Google Benchmark prints it with a "/s": it is a ratio)
// Byte model of a step (each array touched once; gathers of x, v and
// scatters of f hit cache because grid neighbours are close in memory):
//   springs: i, j (2 x 4 B) + rest, k, c (3 x 8 B)                = 32 B
//   nodes:   read x, v, f_ext, f_residual (4 x 24 B), mass, damping,
//            1/m (3 x 8 B); write the 32 B spring-force accumulator
//            entry and read it back (2 x 32 B); write x, v (2 x 24 B)
//                                                                 = 232 B
//   anchors: node (4 B), point (24 B), k, c (2 x 8 B)             = 44 B
// Run: nice -n 10 build-msm/bin/bench_msm_step --benchmark_min_time=0.2
//        --benchmark_repetitions=5 --benchmark_report_aggregates_only=true
#include <benchmark/benchmark.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <optional>
#include <string>
#include <vector>

#include "hapsim/core/msm/msm_step.h"
#include "hapsim/core/scenes/tissue_block/tissue_block.h"

namespace {

using hapsim::core::IntegratorChoice;
using hapsim::core::IntegratorKind;

double StepBytes(const hapsim::core::MsmModel& m) {
  return 32.0 * m.NumSprings() + 232.0 * m.num_nodes + 44.0 * m.NumAnchors();
}

double WorkingSetBytes(const hapsim::core::MsmModel& m) {
  // Every array the step touches: springs 32 B, nodes 4 x 24 + 32 + 3 x 8 B, anchors 44 B.
  return 32.0 * m.NumSprings() + 152.0 * m.num_nodes + 44.0 * m.NumAnchors();
}

// STREAM triad bandwidth [bytes/s] over 3 arrays totalling `bytes`.
double TriadBandwidth(double bytes) {
  const auto n = static_cast<std::size_t>(std::max(1024.0, bytes / 24.0));
  std::vector<double> a(n, 0.0), b(n, 1.0), c(n, 2.0);
  const double s = 3.0;
  double best_s = INFINITY;
  // Repeat until ~50 ms of samples; keep the best pass (STREAM convention).
  double total_s = 0.0;
  for (int rep = 0; rep < 10000 && (rep < 5 || total_s < 0.05); ++rep) {
    const auto t0 = std::chrono::steady_clock::now();
    double* __restrict pa = a.data();
    const double* __restrict pb = b.data();
    const double* __restrict pc = c.data();
    for (std::size_t i = 0; i < n; ++i) pa[i] = pb[i] + s * pc[i];
    benchmark::ClobberMemory();
    const double dt = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    best_s = std::min(best_s, dt);
    total_s += dt;
  }
  benchmark::DoNotOptimize(a.data());
  return 24.0 * static_cast<double>(n) / best_s;
}

// The spring kernel a benchmark runs (default: the fastest this CPU has).
// Both give bit-identical states (tests/core/spring_kernel_test.cpp); the
// portable kernel, the one every CPU runs, is the baseline run side by side
// with the default.
void BM_MsmStep(benchmark::State& bench, IntegratorChoice method, std::optional<hapsim::core::SpringKernel> kernel) {
  hapsim::core::TissueBlockParams p;
  p.grid_nodes = static_cast<int>(bench.range(0));
  p.size_m = 0.003 * (p.grid_nodes - 1);
  const hapsim::core::MsmModel model = hapsim::core::BuildMsmModel(hapsim::core::MakeTissueGridDef(p));
  hapsim::core::MsmState state = hapsim::core::MakeMsmState(model);
  hapsim::core::MsmWorkspace ws = hapsim::core::MakeMsmWorkspace(model);
  if (kernel) ws.spring_kernel = *kernel;
  bench.SetLabel(hapsim::core::SpringKernelName(ws.spring_kernel));
  // A press in the middle so the springs do real work (not all at rest).
  state.f_ext_N(2, (p.grid_nodes / 2) * p.grid_nodes + p.grid_nodes / 2) = -0.5;
  const double triad = TriadBandwidth(WorkingSetBytes(model));
  double cg_iterations = 0.0;
  for (auto _ : bench) {
    const hapsim::core::StepReport r = hapsim::core::StepMsm(model, state, 1e-3, method, ws);
    cg_iterations += r.cg_iterations;
    benchmark::ClobberMemory();
  }
  const auto steps = static_cast<double>(bench.iterations());
  bench.counters["springs"] = model.NumSprings();
  // Spring passes per step: 1 (Euler variants), 2 (midpoint-averaging), 4
  // (RK4); backward Euler: 1 force pass + 1 linearisation + 1 per CG iteration.
  bench.counters["cg_iters_per_step"] = cg_iterations / steps;
  bench.counters["springs_per_s"] = benchmark::Counter(steps * model.NumSprings(), benchmark::Counter::kIsRate);
  bench.counters["working_set_MB"] = WorkingSetBytes(model) / 1e6;
  bench.counters["step_GBps"] = benchmark::Counter(steps * StepBytes(model) / 1e9, benchmark::Counter::kIsRate);
  bench.counters["triad_GBps"] = triad / 1e9;
  bench.counters["bw_fraction"] = benchmark::Counter(steps * StepBytes(model) / triad, benchmark::Counter::kIsRate);
  if (!state.x_m.allFinite()) bench.SkipWithError("state blew up");
}

// With --benchmark_repetitions, also report the best repetition: "max" of
// springs_per_s (on a shared machine the median mixes in other processes).
void Statistics(benchmark::internal::Benchmark* b) {
  b->ComputeStatistics("max", [](const std::vector<double>& v) { return *std::max_element(v.begin(), v.end()); });
}

// Grid sizes giving ~1k, 10k, 33k, 100k, 160k, 210k, 300k, 410k, 640k and
// 1M springs (4 per node): the decades, plus the L2 -> L3 -> DRAM range in
// between, where the rate dips.
void MeshSizes(benchmark::internal::Benchmark* b) {
  for (const int n : {17, 51, 91, 159, 200, 230, 275, 320, 400, 501}) b->Arg(n);
  b->ArgName("grid_nodes")->Unit(benchmark::kMicrosecond);
  Statistics(b);
}

constexpr IntegratorChoice kSymplectic{IntegratorKind::kSymplecticEuler, 0.5};
// The default kernel (the fastest on this CPU), then in the same run the
// portable baseline.
BENCHMARK_CAPTURE(BM_MsmStep, symplectic_euler, kSymplectic, std::nullopt)->Apply(MeshSizes);
BENCHMARK_CAPTURE(BM_MsmStep, symplectic_euler_portable, kSymplectic, hapsim::core::SpringKernel::kPortable)
    ->Apply(MeshSizes);
BENCHMARK_CAPTURE(BM_MsmStep, midpoint_averaging, IntegratorChoice{IntegratorKind::kMidpointAveraging, 0.5},
                  std::nullopt)->Apply(MeshSizes);
BENCHMARK_CAPTURE(BM_MsmStep, rk4, IntegratorChoice{IntegratorKind::kRk4, 0.5}, std::nullopt)
    ->Arg(159)->Arg(501)->Unit(benchmark::kMicrosecond)->Apply(Statistics);
BENCHMARK_CAPTURE(BM_MsmStep, backward_euler, IntegratorChoice{IntegratorKind::kBackwardEuler, 0.5}, std::nullopt)
    ->Arg(159)->Unit(benchmark::kMicrosecond)->Apply(Statistics);

}  // namespace

BENCHMARK_MAIN();
