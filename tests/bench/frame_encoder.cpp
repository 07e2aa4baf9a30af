// Cost of building one viewer frame (EncodeFrame) — the per-viewer work of
// the frame pump, paid once per frame per viewer — against a baseline in the
// same run: a bare scan that quantises every vertex and compares it with the
// last sent value (the least work any delta encoder must do).
//   build/bin/bench_frame_encoder --benchmark_min_time=0.2
#include <random>

#include <benchmark/benchmark.h>

#include "hapsim/service/frame_encoder.h"

namespace {

using hapsim::service::SceneSnapshot;
using hapsim::service::StreamEncoderState;

SceneSnapshot MakeSnapshot(int vertices) {
  SceneSnapshot s;
  s.vertices_m = Eigen::Matrix3Xd::Random(3, vertices) * 0.05;
  s.triangles = std::make_shared<std::vector<std::uint32_t>>(static_cast<std::size_t>(6 * vertices), 0u);
  s.parts = std::make_shared<std::vector<hapsim::core::SurfacePart>>();
  s.layer_names = std::make_shared<std::vector<std::string>>();
  s.topology_version = 1;
  return s;
}

// Moves `fraction` of the vertices by ~0.1 mm (a needle press moves a patch).
void Jiggle(SceneSnapshot* s, double fraction, std::mt19937* rng) {
  std::uniform_int_distribution<Eigen::Index> pick(0, s->vertices_m.cols() - 1);
  const auto moved = static_cast<Eigen::Index>(fraction * static_cast<double>(s->vertices_m.cols()));
  for (Eigen::Index i = 0; i < moved; ++i) s->vertices_m(2, pick(*rng)) += 1e-4;
}

void BM_EncodeDelta(benchmark::State& state) {
  const int n = static_cast<int>(state.range(0));
  const double fraction = static_cast<double>(state.range(1)) / 100.0;
  SceneSnapshot s = MakeSnapshot(n);
  StreamEncoderState enc;
  hapsim::v1::Frame frame;
  hapsim::service::EncodeFrame(s, &enc, &frame);  // keyframe first
  std::mt19937 rng(1);
  std::size_t bytes = 0;
  for (auto _ : state) {
    state.PauseTiming();
    Jiggle(&s, fraction, &rng);
    state.ResumeTiming();
    hapsim::service::EncodeFrame(s, &enc, &frame);
    bytes += frame.ByteSizeLong();
  }
  state.counters["bytes_per_frame"] = static_cast<double>(bytes) / static_cast<double>(state.iterations());
  state.counters["viewers_per_core_at_60Hz"] =
      benchmark::Counter(static_cast<double>(state.iterations()) / 60.0, benchmark::Counter::kIsRate);
}

void BM_Keyframe(benchmark::State& state) {
  SceneSnapshot s = MakeSnapshot(static_cast<int>(state.range(0)));
  hapsim::v1::Frame frame;
  for (auto _ : state) {
    StreamEncoderState enc;
    hapsim::service::EncodeFrame(s, &enc, &frame);
    benchmark::DoNotOptimize(frame.ByteSizeLong());
  }
}

// Baseline: quantise + compare every coordinate, no protobuf.
void BM_BaselineQuantiseScan(benchmark::State& state) {
  const int n = static_cast<int>(state.range(0));
  SceneSnapshot s = MakeSnapshot(n);
  std::vector<std::int32_t> sent(static_cast<std::size_t>(3 * n), 0);
  std::mt19937 rng(1);
  for (auto _ : state) {
    state.PauseTiming();
    Jiggle(&s, 0.05, &rng);
    state.ResumeTiming();
    std::size_t moved = 0;
    for (int v = 0; v < n; ++v) {
      bool changed = false;
      for (int k = 0; k < 3; ++k) {
        const std::int32_t q = hapsim::service::QuantiseCoordinate(s.vertices_m(k, v), 1e-5);
        changed |= q != sent[static_cast<std::size_t>(3 * v + k)];
        sent[static_cast<std::size_t>(3 * v + k)] = q;
      }
      moved += changed;
    }
    benchmark::DoNotOptimize(moved);
  }
}

}  // namespace

// 441: tissue block; 5056: acupuncture layers + needle; 50000: a large organ.
BENCHMARK(BM_BaselineQuantiseScan)->Arg(441)->Arg(5056)->Arg(50000);
BENCHMARK(BM_EncodeDelta)->Args({441, 5})->Args({5056, 5})->Args({50000, 5})->Args({5056, 100});
BENCHMARK(BM_Keyframe)->Arg(441)->Arg(5056)->Arg(50000);
BENCHMARK_MAIN();
