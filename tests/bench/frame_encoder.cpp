// Cost of building one viewer frame (EncodeFrame) — the per-viewer work of
// the frame pump, paid once per frame per viewer — against a baseline in the
// same run: a bare scan that quantises every vertex and compares it with the
// last sent value (the least work any delta encoder must do). With the
// cutting cases: a frame carrying one cutting tick's topology edits (tens
// of triangles) against a plain delta and a keyframe of the same mesh.
//   build/bin/bench_frame_encoder --benchmark_min_time=0.2
#include <random>

#include <benchmark/benchmark.h>

#include "hapsim/core/mesh/mesh_topology.h"
#include "hapsim/runtime/snapshot_ring.h"
#include "hapsim/streaming/frame_encoder.h"

namespace {

using hapsim::service::SceneSnapshot;
using hapsim::service::StreamEncoderState;

// A side x side grid mesh with spare slots for cuts, as a scene holds it,
// and the snapshot / frame-pump state around it.
struct Mesh {
  explicit Mesh(int side)
      : x_m(Eigen::Matrix3Xd::Random(3, side * side + 256) * 0.05),
        topology({.vertex_capacity = static_cast<std::uint32_t>(side * side + 256),
                  .triangle_capacity = static_cast<std::uint32_t>(2 * (side - 1) * (side - 1) + 512),
                  .part_names = {"skin", "wound"},
                  .log_capacity = 4096}),
        ring({static_cast<std::size_t>(x_m.cols()), topology.Triangles().Capacity(), 0, 4096}) {
    for (int v = 0; v < side * side; ++v) topology.AddVertex();
    for (int i = 0; i + 1 < side; ++i)
      for (int j = 0; j + 1 < side; ++j) {
        const auto a = static_cast<std::uint32_t>(i * side + j), b = a + 1,
                   c = a + static_cast<std::uint32_t>(side), d = c + 1;
        topology.AddTriangle(a, c, b, 0);
        topology.AddTriangle(b, c, d, 0);
      }
    topology.Seal();
  }
  std::shared_ptr<const SceneSnapshot> Publish() {
    auto s = ring.Acquire();
    hapsim::service::CopyMesh(x_m, topology, history.End(), s.get());
    history.Absorb(*s);
    return s;
  }
  // Moves `fraction` of the vertices by ~0.1 mm (a press moves a patch).
  void Jiggle(double fraction, std::mt19937* rng) {
    std::uniform_int_distribution<std::uint32_t> pick(0, topology.Vertices().HighWater() - 1);
    const auto moved = static_cast<int>(fraction * topology.Vertices().HighWater());
    for (int i = 0; i < moved; ++i) x_m(2, pick(*rng)) += 1e-4;
  }
  // One cutting tick's edits along a moving line: remove `n` triangles and
  // put `n` new ones (on `n / 2` new vertices) where they were.
  void CutTick(int n, std::uint32_t* cursor) {
    std::vector<std::array<std::uint32_t, 3>> removed;
    while (static_cast<int>(removed.size()) < n) {
      const std::uint32_t t = (*cursor)++ % topology.Triangles().HighWater();
      if (!topology.Triangles().IsLive(t)) continue;
      removed.push_back(topology.TriangleVertices(t));
      topology.RemoveTriangle(t);
    }
    for (int k = 0; k < n; ++k) {
      auto tri = removed[static_cast<std::size_t>(k)];
      if (k % 2 == 0) {
        const std::uint32_t v = topology.AddVertex();
        if (v != hapsim::core::kNoSlot) {
          x_m.col(v) = x_m.col(tri[0]);
          tri[0] = v;
        }
      }
      topology.AddTriangle(tri[0], tri[1], tri[2], 1);
    }
    // Free the vertices no triangle uses any more, so slots recycle.
    for (std::uint32_t v = 0; v < topology.Vertices().HighWater(); ++v)
      if (topology.Vertices().IsLive(v) && topology.VertexUses(v) == 0) topology.RemoveVertex(v);
  }
  Eigen::Matrix3Xd x_m;
  hapsim::core::MeshTopology topology;
  hapsim::service::SnapshotRing ring;
  hapsim::service::TopologyHistory history;
};

int Side(std::int64_t vertices) { return static_cast<int>(std::lround(std::sqrt(static_cast<double>(vertices)))); }

void BM_EncodeDelta(benchmark::State& state) {
  Mesh m(Side(state.range(0)));
  const double fraction = static_cast<double>(state.range(1)) / 100.0;
  StreamEncoderState enc;
  hapsim::v1::Frame frame;
  hapsim::service::EncodeFrame(*m.Publish(), m.history, &enc, &frame);  // keyframe first
  std::mt19937 rng(1);
  std::size_t bytes = 0;
  for (auto _ : state) {
    state.PauseTiming();
    m.Jiggle(fraction, &rng);
    const auto s = m.Publish();
    state.ResumeTiming();
    hapsim::service::EncodeFrame(*s, m.history, &enc, &frame);
    bytes += frame.ByteSizeLong();
  }
  state.counters["bytes_per_frame"] = static_cast<double>(bytes) / static_cast<double>(state.iterations());
  state.counters["viewers_per_core_at_60Hz"] =
      benchmark::Counter(static_cast<double>(state.iterations()) / 60.0, benchmark::Counter::kIsRate);
}

// A cutting tick: `range(1)` triangles replaced, 5 % of the vertices moved.
void BM_EncodeCutTick(benchmark::State& state) {
  Mesh m(Side(state.range(0)));
  StreamEncoderState enc;
  hapsim::v1::Frame frame;
  hapsim::service::EncodeFrame(*m.Publish(), m.history, &enc, &frame);
  std::mt19937 rng(1);
  std::uint32_t cursor = 0;
  std::size_t bytes = 0, keyframes = 0;
  for (auto _ : state) {
    state.PauseTiming();
    m.Jiggle(0.05, &rng);
    m.CutTick(static_cast<int>(state.range(1)), &cursor);
    const auto s = m.Publish();
    state.ResumeTiming();
    hapsim::service::EncodeFrame(*s, m.history, &enc, &frame);
    bytes += frame.ByteSizeLong();
    keyframes += frame.has_keyframe();
  }
  state.counters["bytes_per_frame"] = static_cast<double>(bytes) / static_cast<double>(state.iterations());
  state.counters["keyframes"] = static_cast<double>(keyframes);
}

void BM_Keyframe(benchmark::State& state) {
  Mesh m(Side(state.range(0)));
  const auto s = m.Publish();
  hapsim::v1::Frame frame;
  for (auto _ : state) {
    StreamEncoderState enc;
    hapsim::service::EncodeFrame(*s, m.history, &enc, &frame);
    benchmark::DoNotOptimize(frame.ByteSizeLong());
  }
}

// The tick's share: copying the mesh into a snapshot buffer (once per
// snapshot, whatever the number of viewers) while cutting.
void BM_CopyMeshWhileCutting(benchmark::State& state) {
  Mesh m(Side(state.range(0)));
  std::uint32_t cursor = 0;
  for (auto _ : state) {
    state.PauseTiming();
    m.CutTick(20, &cursor);
    state.ResumeTiming();
    benchmark::DoNotOptimize(m.Publish());
  }
}

// Baseline: quantise + compare every coordinate, no protobuf.
void BM_BaselineQuantiseScan(benchmark::State& state) {
  Mesh m(Side(state.range(0)));
  const auto n = static_cast<int>(m.topology.Vertices().HighWater());
  std::vector<std::int32_t> sent(static_cast<std::size_t>(3 * n), 0);
  std::mt19937 rng(1);
  for (auto _ : state) {
    state.PauseTiming();
    m.Jiggle(0.05, &rng);
    state.ResumeTiming();
    std::size_t moved = 0;
    for (int v = 0; v < n; ++v) {
      bool changed = false;
      for (int k = 0; k < 3; ++k) {
        const std::int32_t q = hapsim::service::QuantiseCoordinate(m.x_m(k, v), 1e-5);
        changed |= q != sent[static_cast<std::size_t>(3 * v + k)];
        sent[static_cast<std::size_t>(3 * v + k)] = q;
      }
      moved += changed;
    }
    benchmark::DoNotOptimize(moved);
  }
}

}  // namespace

// 441: tissue block; 5041: acupuncture-sized; 50176: a large organ (224²).
BENCHMARK(BM_BaselineQuantiseScan)->Arg(441)->Arg(5041)->Arg(50176);
BENCHMARK(BM_EncodeDelta)->Args({441, 5})->Args({5041, 5})->Args({50176, 5})->Args({5041, 100});
BENCHMARK(BM_EncodeCutTick)->Args({5041, 20})->Args({50176, 20})->Args({50176, 60});
BENCHMARK(BM_Keyframe)->Arg(441)->Arg(5041)->Arg(50176);
BENCHMARK(BM_CopyMeshWhileCutting)->Arg(5041)->Arg(50176);
BENCHMARK_MAIN();
