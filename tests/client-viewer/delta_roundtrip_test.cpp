// The viewer's mesh, rebuilt from one keyframe and any sequence of deltas,
// equals the server's mesh within half a quantisation step — also when the
// encoder skips (coalesces) snapshots, as it does for slow viewers.
#include <random>

#include <gtest/gtest.h>

#include "hapsim/service/frame_encoder.h"
#include "hapsim/viewer/mesh_cache.h"

namespace hapsim {
namespace {

service::SceneSnapshot GridSnapshot(int n, std::uint64_t topology_version) {
  service::SceneSnapshot s;
  s.vertices_m.resize(3, n * n);
  auto tris = std::make_shared<std::vector<std::uint32_t>>();
  for (int i = 0; i < n; ++i) {
    for (int j = 0; j < n; ++j) s.vertices_m.col(i * n + j) = Eigen::Vector3d(i * 0.003, j * 0.003, 0.0);
  }
  for (int i = 0; i + 1 < n; ++i) {
    for (int j = 0; j + 1 < n; ++j) {
      const auto a = static_cast<std::uint32_t>(i * n + j);
      const auto b = a + 1, c = a + static_cast<std::uint32_t>(n), d = c + 1;
      tris->insert(tris->end(), {a, c, b, b, c, d});
    }
  }
  s.triangles = tris;
  s.parts = std::make_shared<std::vector<core::SurfacePart>>(
      std::vector<core::SurfacePart>{{"tissue", 0, static_cast<std::uint32_t>(tris->size() / 3)}});
  s.layer_names = std::make_shared<std::vector<std::string>>(std::vector<std::string>{"tissue"});
  s.topology_version = topology_version;
  return s;
}

double MaxError(const viewer::MeshCache& cache, const service::SceneSnapshot& s) {
  return (cache.Vertices_m() - s.vertices_m).cwiseAbs().maxCoeff();
}

TEST(DeltaRoundTrip, ViewerMeshEqualsServerMeshWithinHalfQuantumUnderCoalescing) {
  std::mt19937 rng(7);
  std::normal_distribution<double> jiggle(0.0, 2e-4);   // ~20 quanta
  std::uniform_real_distribution<double> coin(0.0, 1.0);
  service::StreamEncoderState encoder;
  encoder.quantum_m = 1e-5;
  viewer::MeshCache cache;
  hapsim::v1::Frame frame;
  service::SceneSnapshot s = GridSnapshot(12, 1);
  int sent = 0, skipped = 0;
  for (int step = 0; step < 400; ++step) {
    // Physics moves a random subset of vertices (and sometimes none).
    for (Eigen::Index v = 0; v < s.vertices_m.cols(); ++v) {
      if (coin(rng) < 0.3) s.vertices_m.col(v) += Eigen::Vector3d(jiggle(rng), jiggle(rng), jiggle(rng));
    }
    s.id = static_cast<std::uint64_t>(step + 1);
    if (coin(rng) < 0.4) {  // the stream was busy: this snapshot is coalesced away
      ++skipped;
      continue;
    }
    service::EncodeFrame(s, &encoder, &frame);
    ASSERT_EQ(cache.Apply(frame), viewer::ApplyResult::kApplied) << "step " << step;
    ++sent;
    EXPECT_LE(MaxError(cache, s), 0.5 * encoder.quantum_m + 1e-12) << "step " << step;
  }
  EXPECT_GT(sent, 100);
  EXPECT_GT(skipped, 100);
  EXPECT_EQ(cache.last_seq(), static_cast<std::uint64_t>(sent - 1));  // seqs contiguous despite skips
}

TEST(DeltaRoundTrip, UnchangedMeshSendsEmptyDeltas) {
  service::StreamEncoderState encoder;
  viewer::MeshCache cache;
  hapsim::v1::Frame frame;
  const auto s = GridSnapshot(5, 1);
  service::EncodeFrame(s, &encoder, &frame);
  ASSERT_TRUE(frame.has_keyframe());
  ASSERT_EQ(cache.Apply(frame), viewer::ApplyResult::kApplied);
  service::EncodeFrame(s, &encoder, &frame);
  ASSERT_TRUE(frame.has_delta());
  EXPECT_EQ(frame.delta().index_gaps_size(), 0);
  EXPECT_EQ(cache.Apply(frame), viewer::ApplyResult::kApplied);
}

TEST(DeltaRoundTrip, TopologyChangeSendsKeyframe) {
  service::StreamEncoderState encoder;
  viewer::MeshCache cache;
  hapsim::v1::Frame frame;
  service::EncodeFrame(GridSnapshot(4, 1), &encoder, &frame);
  ASSERT_EQ(cache.Apply(frame), viewer::ApplyResult::kApplied);
  const auto cut = GridSnapshot(6, 2);  // more vertices, new version
  service::EncodeFrame(cut, &encoder, &frame);
  ASSERT_TRUE(frame.has_keyframe());
  ASSERT_EQ(cache.Apply(frame), viewer::ApplyResult::kApplied);
  EXPECT_EQ(cache.vertex_count(), 36u);
  EXPECT_EQ(cache.topology_version(), 2u);
  EXPECT_LE(MaxError(cache, cut), 0.5e-5 + 1e-12);
}

TEST(MeshCache, DetectsSeqGap) {
  service::StreamEncoderState encoder;
  viewer::MeshCache cache;
  hapsim::v1::Frame f0, f1, f2;
  auto s = GridSnapshot(4, 1);
  service::EncodeFrame(s, &encoder, &f0);
  s.vertices_m(2, 3) += 0.001;
  service::EncodeFrame(s, &encoder, &f1);  // lost in transit
  s.vertices_m(2, 5) += 0.001;
  service::EncodeFrame(s, &encoder, &f2);
  ASSERT_EQ(cache.Apply(f0), viewer::ApplyResult::kApplied);
  EXPECT_EQ(cache.Apply(f2), viewer::ApplyResult::kGap);
}

TEST(MeshCache, DetectsTopologyMismatch) {
  service::StreamEncoderState encoder;
  viewer::MeshCache cache;
  hapsim::v1::Frame f0, f1;
  auto s = GridSnapshot(4, 1);
  service::EncodeFrame(s, &encoder, &f0);
  service::EncodeFrame(s, &encoder, &f1);
  f1.set_topology_version(9);
  ASSERT_EQ(cache.Apply(f0), viewer::ApplyResult::kApplied);
  EXPECT_EQ(cache.Apply(f1), viewer::ApplyResult::kTopologyMismatch);
}

TEST(MeshCache, RefusesMalformedFramesWithoutChangingTheMesh) {
  service::StreamEncoderState encoder;
  viewer::MeshCache cache;
  hapsim::v1::Frame key, bad;
  const auto s = GridSnapshot(4, 1);
  service::EncodeFrame(s, &encoder, &key);
  ASSERT_EQ(cache.Apply(key), viewer::ApplyResult::kApplied);
  const Eigen::Matrix3Xd before = cache.Vertices_m();
  bad.set_seq(1);
  bad.set_topology_version(1);
  bad.mutable_delta()->add_index_gaps(3);
  bad.mutable_delta()->add_index_gaps(1000);  // out of range
  for (int k = 0; k < 6; ++k) bad.mutable_delta()->add_position_dq(5);
  EXPECT_EQ(cache.Apply(bad), viewer::ApplyResult::kMalformed);
  EXPECT_EQ((cache.Vertices_m() - before).norm(), 0.0);  // nothing half-applied
  hapsim::v1::Frame bad_key = key;
  bad_key.mutable_keyframe()->set_triangles(0, 99);
  EXPECT_EQ(cache.Apply(bad_key), viewer::ApplyResult::kMalformed);
  EXPECT_EQ(cache.vertex_count(), 16u);
}

TEST(MeshCache, DeltaBeforeKeyframeNeedsKeyframe) {
  viewer::MeshCache cache;
  hapsim::v1::Frame f;
  f.mutable_delta();
  EXPECT_EQ(cache.Apply(f), viewer::ApplyResult::kNeedKeyframe);
}

}  // namespace
}  // namespace hapsim
