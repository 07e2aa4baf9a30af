// Radial SH depth query (inside/outside + depth below every layer) against
// Lmax: one basis evaluation, then k-term dot products per surface. The
// acupuncture scene runs one 4-surface query per tick.
#include <benchmark/benchmark.h>

#include "hapsim/core/scenes/acupuncture/acupuncture_body.h"
#include "hapsim/core/shf/real_spherical_harmonics.h"

namespace {

using namespace hapsim::core;

void BM_ShDepthQuery_FourLayers(benchmark::State& state) {
  const int lmax = static_cast<int>(state.range(0));
  LayeredShBody body = MakeAcupunctureBody(PaperTissueLayers(), lmax, std::max(600, 3 * (lmax + 1) * (lmax + 1)));
  Eigen::VectorXd depth(body.NumSurfaces());
  int k = 0;
  for (auto _ : state) {
    const double s = 1e-4 * (k++ % 64);
    body.Depths_m(Eigen::Vector3d(s, -0.5 * s, -s), depth);
    benchmark::DoNotOptimize(depth.data());
  }
  state.counters["k"] = (lmax + 1) * (lmax + 1);
}
BENCHMARK(BM_ShDepthQuery_FourLayers)->Arg(4)->Arg(8)->Arg(12)->Arg(16)->Arg(20)->Arg(30)->Unit(benchmark::kMicrosecond);

void BM_RealShBasis(benchmark::State& state) {
  const RealShBasis basis(static_cast<int>(state.range(0)));
  Eigen::VectorXd y(basis.Size());
  double theta = 0.3;
  for (auto _ : state) {
    basis.Evaluate(theta, 1.1, y);
    theta += 1e-9;
    benchmark::DoNotOptimize(y.data());
  }
}
BENCHMARK(BM_RealShBasis)->Arg(8)->Arg(30)->Unit(benchmark::kMicrosecond);

}  // namespace

BENCHMARK_MAIN();
