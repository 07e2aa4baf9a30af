// One acupuncture scene tick (SH depth query, force-net solve, springback,
// local force model, displayed patches and needle), and its parts.
// Target: whole tick <= 100 µs single-threaded.
#include <time.h>

#include <algorithm>

#include <benchmark/benchmark.h>

#include "hapsim/core/needle/force_net.h"
#include "hapsim/core/needle/tissue_layers.h"
#include "hapsim/core/scenes/acupuncture/acupuncture_scene.h"
#include "hapsim/core/shape_matching/shape_matching.h"

namespace {

using namespace hapsim::core;

double ThreadCpu_s() {
  timespec ts{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
  return static_cast<double>(ts.tv_sec) + 1e-9 * static_cast<double>(ts.tv_nsec);
}

ToolInput Vertical(double z_m, double vz) {
  ToolInput t;
  t.valid = true;
  t.tip_W_m = Eigen::Vector3d(0, 0, z_m);
  t.velocity_W_m_per_s = Eigen::Vector3d(0, 0, vz);
  return t;
}

// Worst case: skin and fat punctured and springing back, muscle (the
// largest net, 271 particles) being pressed; all three patches displaced.
void BM_AcupunctureTick_PressingMuscle(benchmark::State& state) {
  AcupunctureParams p;
  p.shf_lmax = static_cast<int>(state.range(0));
  AcupunctureScene s(p);
  double z = 1e-3;
  while (!(s.PuncturedLayers() == 2 && s.Pressing())) s.Step(Vertical(z -= 5e-6, -5e-3), 1e-3);
  const double z_press = z;
  int k = 0;
  for (auto _ : state) {
    s.Step(Vertical(z_press - 1e-6 * (k++ % 16), -5e-3), 1e-3);
    benchmark::DoNotOptimize(s.ToolForce_W_N());
  }
  if (!s.Pressing() || s.PuncturedLayers() != 2) state.SkipWithError("left the pressing-muscle state");
}
BENCHMARK(BM_AcupunctureTick_PressingMuscle)->Arg(8)->Arg(12)->Unit(benchmark::kMicrosecond);

// Average over a whole insertion to 30 mm and back at 5 mm/s (12 800 ticks);
// counter max_us = the slowest single tick seen, in thread CPU time so that
// preemption on the shared machine does not count (contact start: net
// placed, normal by finite differences, patch neighbourhood selected).
void BM_AcupunctureTick_InsertionCycle(benchmark::State& state) {
  AcupunctureScene s{AcupunctureParams{}};
  constexpr int kHalf = 6400;
  int k = 0;
  double max_s = 0.0;
  for (auto _ : state) {
    const int i = k++ % (2 * kHalf);
    const bool in = i < kHalf;
    const double t0 = ThreadCpu_s();
    s.Step(Vertical(2e-3 - 5e-6 * (in ? i : 2 * kHalf - i), in ? -5e-3 : 5e-3), 1e-3);
    max_s = std::max(max_s, ThreadCpu_s() - t0);
    benchmark::DoNotOptimize(s.ToolForce_W_N());
  }
  state.counters["max_us"] = 1e6 * max_s;
}
BENCHMARK(BM_AcupunctureTick_InsertionCycle)->Unit(benchmark::kMicrosecond);

void BM_ForceNetSolve_Muscle(benchmark::State& state) {
  const ForceNetModel net = BuildForceNet(ForceNetDefFor(PaperTissueLayers()[2]));  // muscle
  ForceNetState s = MakeForceNetState(net);
  PlaceForceNet(net, Eigen::Vector3d::Zero(), Eigen::Vector3d::UnitZ(), s);
  int k = 0;
  for (auto _ : state) {
    SolveForceNet(net, Eigen::Vector3d(0, 0, -1e-4 - 1e-7 * (k++ % 16)), s);
    benchmark::DoNotOptimize(NetReactionOnTip_W_N(net, s));
  }
}
BENCHMARK(BM_ForceNetSolve_Muscle)->Unit(benchmark::kMicrosecond);

void BM_SpringbackStep_SkinNet(benchmark::State& state) {
  const ForceNetModel net = BuildForceNet(ForceNetDefFor(PaperTissueLayers()[0]));  // skin
  ForceNetState s = MakeForceNetState(net);
  PlaceForceNet(net, Eigen::Vector3d::Zero(), Eigen::Vector3d::UnitZ(), s);
  SolveForceNet(net, Eigen::Vector3d(0, 0, -1e-4), s);
  Eigen::VectorXd eta = Eigen::VectorXd::Ones(net.topology.NumNodes());
  const Eigen::VectorXd mass = Eigen::VectorXd::Ones(net.topology.NumNodes());
  for (auto _ : state) {
    SpringbackStep(s.rest_W_m, mass, 0.02, s.x_W_m, eta);
    benchmark::DoNotOptimize(s.x_W_m.data());
  }
}
BENCHMARK(BM_SpringbackStep_SkinNet)->Unit(benchmark::kMicrosecond);

}  // namespace

BENCHMARK_MAIN();
