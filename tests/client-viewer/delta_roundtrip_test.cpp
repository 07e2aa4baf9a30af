// The viewer's mesh, rebuilt from one keyframe and any sequence of deltas
// and topology edits, equals the server's mesh: the same live vertex and
// triangle slots, the same triangles and parts, positions within half a
// quantisation step — under random interleavings of vertex moves, removals
// and additions, with snapshots coalesced away (slow viewers) and frames
// lost (the viewer resubscribes), through the real snapshot copy
// (CopyMesh), the frame pump's TopologyHistory, the encoder and the cache.
#include <cmath>
#include <functional>
#include <random>
#include <string>
#include <tuple>
#include <vector>

#include <gtest/gtest.h>

#include "hapsim/core/mesh/mesh_topology.h"
#include "hapsim/streaming/frame_encoder.h"
#include "hapsim/runtime/snapshot_ring.h"
#include "hapsim/viewer/mesh_cache.h"

namespace hapsim {
namespace {

constexpr double kQuantum_m = 1e-5;

// A server-side mesh: positions per slot and the topology, as a scene holds them.
struct ServerMesh {
  Eigen::Matrix3Xd x_m;
  core::MeshTopology topology;
};

ServerMesh Grid(int n, std::uint32_t spare_vertices, std::uint32_t spare_triangles, std::size_t log_capacity) {
  const auto nv = static_cast<std::uint32_t>(n * n);
  ServerMesh m{Eigen::Matrix3Xd::Zero(3, nv + spare_vertices),
               core::MeshTopology({.vertex_capacity = nv + spare_vertices,
                                   .triangle_capacity = static_cast<std::uint32_t>(2 * (n - 1) * (n - 1)) + spare_triangles,
                                   .part_names = {"skin", "wound"},
                                   .log_capacity = log_capacity})};
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j) {
      const std::uint32_t v = m.topology.AddVertex();
      m.x_m.col(v) = Eigen::Vector3d(i * 0.003, j * 0.003, 0.0);
    }
  for (int i = 0; i + 1 < n; ++i)
    for (int j = 0; j + 1 < n; ++j) {
      const auto a = static_cast<std::uint32_t>(i * n + j), b = a + 1, c = a + static_cast<std::uint32_t>(n), d = c + 1;
      m.topology.AddTriangle(a, c, b, 0);
      m.topology.AddTriangle(b, c, d, 0);
    }
  m.topology.Seal();
  return m;
}

// The session and frame pump side: a snapshot ring, what the pump has taken.
struct Pipe {
  explicit Pipe(const ServerMesh& m)
      : ring({static_cast<std::size_t>(m.x_m.cols()), m.topology.Triangles().Capacity(), 0,
              m.topology.Log().Capacity()}),
        part_names(std::make_shared<const std::vector<std::string>>(m.topology.PartNames())) {}
  // Tick: publish a snapshot. Pump: absorb its edits.
  std::shared_ptr<const service::SceneSnapshot> Publish(const ServerMesh& m) {
    auto s = ring.Acquire();
    service::CopyMesh(m.x_m, m.topology, taken, s.get());
    s->id = ++id;
    s->part_names = part_names;
    history.Absorb(*s);
    taken = history.End();
    return s;
  }
  service::SnapshotRing ring;
  std::shared_ptr<const std::vector<std::string>> part_names;
  service::TopologyHistory history;
  std::uint64_t taken = 0, id = 0;
};

// Every way the viewer's mesh could differ from the server's.
void ExpectSameMesh(const viewer::MeshCache& cache, const ServerMesh& m, const char* when) {
  SCOPED_TRACE(when);
  const core::MeshTopology& t = m.topology;
  ASSERT_EQ(cache.topology_version(), t.Version());
  ASSERT_EQ(cache.live_vertex_count(), t.Vertices().LiveCount());
  ASSERT_EQ(cache.live_triangle_count(), t.Triangles().LiveCount());
  const Eigen::Matrix3Xd v = cache.Vertices_m();
  for (std::uint32_t s = 0; s < t.Vertices().HighWater(); ++s) {
    ASSERT_EQ(cache.vertex_live(s), t.Vertices().IsLive(s)) << "vertex slot " << s;
    if (!t.Vertices().IsLive(s)) continue;
    ASSERT_LE((v.col(s) - m.x_m.col(s)).cwiseAbs().maxCoeff(), 0.5 * kQuantum_m + 1e-12) << "vertex slot " << s;
  }
  for (std::uint32_t s = 0; s < t.Triangles().HighWater(); ++s) {
    ASSERT_EQ(cache.triangle_live(s), t.Triangles().IsLive(s)) << "triangle slot " << s;
    if (!t.Triangles().IsLive(s)) continue;
    ASSERT_EQ(cache.triangle(s), t.TriangleVertices(s)) << "triangle slot " << s;
    ASSERT_EQ(cache.triangle_part(s), t.TrianglePart(s)) << "triangle slot " << s;
  }
}

// One random topology edit of the kind a cut makes: remove a triangle (and
// any vertex it leaves unused), or add a vertex near a live one and a
// triangle joining it to two live vertices.
void RandomEdit(ServerMesh& m, std::mt19937& rng) {
  core::MeshTopology& t = m.topology;
  std::uniform_real_distribution<double> coin(0.0, 1.0);
  if (coin(rng) < 0.5 && t.Triangles().LiveCount() > 4) {
    std::uniform_int_distribution<std::uint32_t> pick(0, t.Triangles().HighWater() - 1);
    std::uint32_t tri = pick(rng);
    while (!t.Triangles().IsLive(tri)) tri = pick(rng);
    const auto verts = t.TriangleVertices(tri);
    t.RemoveTriangle(tri);
    for (const auto v : verts)
      if (t.VertexUses(v) == 0) t.RemoveVertex(v);
    return;
  }
  std::vector<std::uint32_t> live;
  for (std::uint32_t v = 0; v < t.Vertices().HighWater(); ++v)
    if (t.Vertices().IsLive(v)) live.push_back(v);
  if (live.size() < 2) return;
  std::uniform_int_distribution<std::size_t> pick(0, live.size() - 1);
  const std::uint32_t a = live[pick(rng)];
  std::uint32_t b = live[pick(rng)];
  while (b == a) b = live[pick(rng)];
  const std::uint32_t c = t.AddVertex();
  if (c == core::kNoSlot) return;
  m.x_m.col(c) = 0.5 * (m.x_m.col(a) + m.x_m.col(b)) + Eigen::Vector3d(0, 0, 1e-3 * coin(rng));
  if (t.AddTriangle(a, b, c, 1) == core::kNoSlot) t.RemoveVertex(c);
}

TEST(TopologyRoundTrip, ViewerMeshEqualsServerMeshUnderRandomEditsCoalescingAndLoss) {
  std::mt19937 rng(11);
  std::normal_distribution<double> jiggle(0.0, 2e-4);
  std::uniform_real_distribution<double> coin(0.0, 1.0);
  ServerMesh m = Grid(10, 60, 120, 4096);
  Pipe pipe(m);
  service::StreamEncoderState encoder;
  encoder.quantum_m = kQuantum_m;
  viewer::MeshCache cache;
  hapsim::v1::Frame frame;
  int sent = 0, skipped = 0, lost = 0, keyframes = 0, topology_deltas = 0, resets = 0;
  for (int step = 0; step < 1500; ++step) {
    for (Eigen::Index v = 0; v < m.x_m.cols(); ++v) {
      if (coin(rng) < 0.3) m.x_m.col(v) += Eigen::Vector3d(jiggle(rng), jiggle(rng), jiggle(rng));
    }
    const double r = coin(rng);
    if (r < 0.25) {
      const int edits = 1 + static_cast<int>(6 * coin(rng));
      for (int e = 0; e < edits; ++e) RandomEdit(m, rng);
    } else if (r < 0.253) {
      m.topology.Reset();  // the scene was reset: its log restarts
      ++resets;
    }
    const auto snapshot = pipe.Publish(m);
    if (coin(rng) < 0.4) {  // the stream was busy: this snapshot is coalesced away
      ++skipped;
      continue;
    }
    service::EncodeFrame(*snapshot, pipe.history, &encoder, &frame);
    if (coin(rng) < 0.02) {  // lost: the next frame shows a gap and the viewer resubscribes
      ++lost;
      continue;
    }
    const viewer::ApplyResult applied = cache.Apply(frame);
    if (applied == viewer::ApplyResult::kGap) {
      cache.Invalidate();
      encoder = service::StreamEncoderState{};  // a new stream
      encoder.quantum_m = kQuantum_m;
      continue;
    }
    ASSERT_EQ(applied, viewer::ApplyResult::kApplied) << "step " << step;
    ++sent;
    keyframes += frame.has_keyframe() ? 1 : 0;
    topology_deltas += frame.has_topology() ? 1 : 0;
    ExpectSameMesh(cache, m, ("step " + std::to_string(step)).c_str());
    if (HasFatalFailure()) return;
  }
  EXPECT_GT(sent, 600);
  EXPECT_GT(skipped, 400);
  EXPECT_GT(lost, 5);
  EXPECT_GT(topology_deltas, 150);  // edits travel as deltas...
  EXPECT_LE(keyframes, 1 + lost + resets);  // ...keyframes only at the start, after a loss or a reset
}

TEST(TopologyRoundTrip, AStreamBeyondTheHistoryGetsAKeyframe) {
  ServerMesh m = Grid(6, 40, 80, 4096);
  Pipe pipe(m);
  service::TopologyHistory small(8);  // the pump keeps only 8 edits
  service::StreamEncoderState encoder;
  viewer::MeshCache cache;
  hapsim::v1::Frame frame;
  auto s = pipe.Publish(m);
  small.Absorb(*s);
  service::EncodeFrame(*s, small, &encoder, &frame);
  ASSERT_EQ(cache.Apply(frame), viewer::ApplyResult::kApplied);
  std::mt19937 rng(3);
  for (int e = 0; e < 30; ++e) RandomEdit(m, rng);  // more edits than the history keeps
  s = pipe.Publish(m);
  small.Absorb(*s);
  service::EncodeFrame(*s, small, &encoder, &frame);
  EXPECT_TRUE(frame.has_keyframe());
  ASSERT_EQ(cache.Apply(frame), viewer::ApplyResult::kApplied);
  ExpectSameMesh(cache, m, "after the keyframe");
}

TEST(TopologyRoundTrip, UnchangedMeshSendsEmptyDeltas) {
  ServerMesh m = Grid(5, 0, 0, 16);
  Pipe pipe(m);
  service::StreamEncoderState encoder;
  viewer::MeshCache cache;
  hapsim::v1::Frame frame;
  service::EncodeFrame(*pipe.Publish(m), pipe.history, &encoder, &frame);
  ASSERT_TRUE(frame.has_keyframe());
  ASSERT_EQ(cache.Apply(frame), viewer::ApplyResult::kApplied);
  service::EncodeFrame(*pipe.Publish(m), pipe.history, &encoder, &frame);
  ASSERT_TRUE(frame.has_delta());
  EXPECT_FALSE(frame.has_topology());
  EXPECT_EQ(frame.delta().index_gaps_size(), 0);
  EXPECT_EQ(cache.Apply(frame), viewer::ApplyResult::kApplied);
}

TEST(MeshCache, DetectsSeqGap) {
  ServerMesh m = Grid(4, 0, 0, 16);
  Pipe pipe(m);
  service::StreamEncoderState encoder;
  viewer::MeshCache cache;
  hapsim::v1::Frame f0, f1, f2;
  service::EncodeFrame(*pipe.Publish(m), pipe.history, &encoder, &f0);
  m.x_m(2, 3) += 0.001;
  service::EncodeFrame(*pipe.Publish(m), pipe.history, &encoder, &f1);  // lost in transit
  m.x_m(2, 5) += 0.001;
  service::EncodeFrame(*pipe.Publish(m), pipe.history, &encoder, &f2);
  ASSERT_EQ(cache.Apply(f0), viewer::ApplyResult::kApplied);
  EXPECT_EQ(cache.Apply(f2), viewer::ApplyResult::kGap);
}

TEST(MeshCache, DetectsTopologyMismatch) {
  ServerMesh m = Grid(4, 0, 0, 16);
  Pipe pipe(m);
  service::StreamEncoderState encoder;
  viewer::MeshCache cache;
  hapsim::v1::Frame f0, f1;
  service::EncodeFrame(*pipe.Publish(m), pipe.history, &encoder, &f0);
  service::EncodeFrame(*pipe.Publish(m), pipe.history, &encoder, &f1);
  f1.set_topology_version(9);
  ASSERT_EQ(cache.Apply(f0), viewer::ApplyResult::kApplied);
  EXPECT_EQ(cache.Apply(f1), viewer::ApplyResult::kTopologyMismatch);
}

// A cache that refuses a frame is exactly as it was before it.
class MalformedFrames : public ::testing::Test {
 protected:
  void SetUp() override {
    m = Grid(4, 4, 8, 64);
    pipe = std::make_unique<Pipe>(m);
    service::EncodeFrame(*pipe->Publish(m), pipe->history, &encoder, &key);
    ASSERT_EQ(cache.Apply(key), viewer::ApplyResult::kApplied);
    before = cache.Vertices_m();
    next.set_seq(1);
    next.set_topology_version(m.topology.Version() + 1);
    next.mutable_delta();
    next.mutable_topology()->set_from_version(m.topology.Version());
  }
  void ExpectRefusedAndUnchanged(const hapsim::v1::Frame& f) {
    std::string why;
    EXPECT_EQ(cache.Apply(f, &why), viewer::ApplyResult::kMalformed);
    EXPECT_FALSE(why.empty());
    EXPECT_EQ((cache.Vertices_m() - before).norm(), 0.0);
    ExpectSameMesh(cache, m, "after a refused frame");
    EXPECT_EQ(cache.last_seq(), 0u);
  }
  // Appends edit words; the frame's version steps by the number of edits
  // (one per version), so each test reaches the fault it is about.
  void Edits(std::initializer_list<std::uint32_t> e) {
    for (const auto x : e) next.mutable_topology()->add_edits(x);
    std::uint64_t count = 0;
    const auto& words = next.topology().edits();
    for (int i = 0; i < words.size(); i += words[i] == 2 ? 6 : 2) ++count;
    next.set_topology_version(next.topology().from_version() + count);
  }
  ServerMesh m = Grid(2, 0, 0, 0);
  std::unique_ptr<Pipe> pipe;
  service::StreamEncoderState encoder;
  viewer::MeshCache cache;
  hapsim::v1::Frame key, next;
  Eigen::Matrix3Xd before;
};

TEST_F(MalformedFrames, DeltaIndexOutOfRange) {
  next.clear_topology();
  next.set_topology_version(m.topology.Version());
  next.mutable_delta()->add_index_gaps(3);
  next.mutable_delta()->add_index_gaps(1000);
  for (int k = 0; k < 6; ++k) next.mutable_delta()->add_position_dq(5);
  ExpectRefusedAndUnchanged(next);
}
TEST_F(MalformedFrames, RemovingAVertexATriangleStillUses) { Edits({1, 0}); ExpectRefusedAndUnchanged(next); }
TEST_F(MalformedFrames, AddingALiveSlot) { Edits({0, 3}); ExpectRefusedAndUnchanged(next); }
TEST_F(MalformedFrames, AddingBeyondTheCapacity) { Edits({0, 20}); ExpectRefusedAndUnchanged(next); }
TEST_F(MalformedFrames, TriangleOnAFreeVertex) { Edits({2, 18, 0, 0, 1, 17}); ExpectRefusedAndUnchanged(next); }
TEST_F(MalformedFrames, TriangleWithAnUnknownPart) { Edits({2, 18, 7, 0, 1, 2}); ExpectRefusedAndUnchanged(next); }
TEST_F(MalformedFrames, TruncatedEdit) { Edits({2, 18, 0, 0}); ExpectRefusedAndUnchanged(next); }
TEST_F(MalformedFrames, UnknownEditKind) { Edits({9, 1}); ExpectRefusedAndUnchanged(next); }
TEST_F(MalformedFrames, EditCountDiffersFromTheVersionStep) {
  Edits({0, 16});  // a valid edit...
  next.set_topology_version(next.topology().from_version() + 2);  // ...claimed as two versions
  ExpectRefusedAndUnchanged(next);
}
TEST_F(MalformedFrames, AGoodEditThenABadOneChangesNothing) {
  Edits({0, 16, 3, 0, 3, 0});  // add vertex 16, remove triangle 0, then remove it again
  ExpectRefusedAndUnchanged(next);
}
TEST_F(MalformedFrames, MovingAVertexTheEditsRemoved) {
  // Remove the two triangles of the corner cell (slots 4, 5) and its corner
  // vertex 3 (valid so far), then move vertex 3.
  Edits({3, 4, 3, 5, 1, 3});
  next.mutable_delta()->add_index_gaps(3);
  for (int k = 0; k < 3; ++k) next.mutable_delta()->add_position_dq(1);
  ExpectRefusedAndUnchanged(next);
}
TEST_F(MalformedFrames, KeyframeTriangleOnAnUnknownVertex) {
  hapsim::v1::Frame bad = key;
  bad.mutable_keyframe()->set_triangles(0, 99);
  ExpectRefusedAndUnchanged(bad);
}

// Row 63 of docs/reliability.md: every way a keyframe can be malformed is
// refused whole, with the reason, and the cache keeps the mesh it had.
TEST_F(MalformedFrames, EveryKeyframeFaultIsRefusedWholeSayingWhy) {
  using Mutation = std::function<void(hapsim::v1::Keyframe&)>;
  const std::vector<std::tuple<const char*, Mutation, const char*>> faults = {
      {"zero quantum", [](auto& k) { k.set_quantum_m(0.0); }, "bad quantum"},
      {"negative quantum", [](auto& k) { k.set_quantum_m(-1e-5); }, "bad quantum"},
      {"NaN quantum", [](auto& k) { k.set_quantum_m(std::nan("")); }, "bad quantum"},
      {"infinite quantum", [](auto& k) { k.set_quantum_m(HUGE_VAL); }, "bad quantum"},
      {"a lone coordinate", [](auto& k) { k.add_positions_q(1); }, "positions not a multiple of 3"},
      {"a part too many", [](auto& k) { k.add_triangle_parts(0); }, "triangles and triangle parts do not match"},
      {"vertex capacity below the slots", [](auto& k) { k.set_vertex_capacity(1); }, "slot capacities"},
      {"vertex capacity above 2^26", [](auto& k) { k.set_vertex_capacity((1u << 26) + 1); }, "slot capacities"},
      {"triangle capacity below the slots", [](auto& k) { k.set_triangle_capacity(1); }, "slot capacities"},
      {"a free vertex slot past the end", [](auto& k) { k.add_free_vertices(100000); }, "bad free vertex slot"},
      {"a free vertex slot twice", [](auto& k) { k.add_free_vertices(15); k.add_free_vertices(15); },
       "bad free vertex slot"},
      {"a free triangle slot past the end", [](auto& k) { k.add_free_triangles(100000); }, "bad free triangle slot"},
      {"a repeated vertex in a triangle", [](auto& k) { k.set_triangles(1, k.triangles(0)); }, "repeated"},
      {"an unknown part", [](auto& k) { k.set_triangle_parts(0, 99); }, "unknown part"},
  };
  for (const auto& [name, mutate, reason] : faults) {
    hapsim::v1::Frame bad = key;
    bad.set_seq(7);
    mutate(*bad.mutable_keyframe());
    std::string why;
    EXPECT_EQ(cache.Apply(bad, &why), viewer::ApplyResult::kMalformed) << name;
    EXPECT_NE(why.find(reason), std::string::npos) << name << ": " << why;
    EXPECT_EQ((cache.Vertices_m() - before).norm(), 0.0) << name;
    ExpectSameMesh(cache, m, name);
    EXPECT_EQ(cache.last_seq(), 0u) << name;
  }
}

// Row 63, deltas: a position count that is not 3 per index, an index that
// does not increase, and a frame with neither keyframe nor delta.
TEST_F(MalformedFrames, EveryDeltaFaultIsRefusedWholeSayingWhy) {
  next.clear_topology();
  next.set_topology_version(m.topology.Version());
  hapsim::v1::Frame short_dq = next;
  short_dq.mutable_delta()->add_index_gaps(1);
  short_dq.mutable_delta()->add_position_dq(4);
  short_dq.mutable_delta()->add_position_dq(4);
  hapsim::v1::Frame repeated_index = next;
  repeated_index.mutable_delta()->add_index_gaps(2);
  repeated_index.mutable_delta()->add_index_gaps(0);  // vertex 2 again
  for (int k = 0; k < 6; ++k) repeated_index.mutable_delta()->add_position_dq(3);
  hapsim::v1::Frame empty;
  empty.set_seq(1);
  const std::vector<std::tuple<const char*, hapsim::v1::Frame, const char*>> faults = {
      {"two values for one index", short_dq, "3 position values per index"},
      {"an index repeated", repeated_index, "not increasing"},
      {"neither keyframe nor delta", empty, "neither keyframe nor delta"},
  };
  for (const auto& [name, frame, reason] : faults) {
    std::string why;
    EXPECT_EQ(cache.Apply(frame, &why), viewer::ApplyResult::kMalformed) << name;
    EXPECT_NE(why.find(reason), std::string::npos) << name << ": " << why;
    EXPECT_EQ((cache.Vertices_m() - before).norm(), 0.0) << name;
    ExpectSameMesh(cache, m, name);
    EXPECT_EQ(cache.last_seq(), 0u) << name;
  }
}

TEST(MeshCache, DeltaBeforeKeyframeNeedsKeyframe) {
  viewer::MeshCache cache;
  hapsim::v1::Frame f;
  f.mutable_delta();
  EXPECT_EQ(cache.Apply(f), viewer::ApplyResult::kNeedKeyframe);
}

}  // namespace
}  // namespace hapsim
