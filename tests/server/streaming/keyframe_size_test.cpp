// Any mesh the server accepts must reach every viewer: the
// keyframe of each scene at its largest accepted mesh fits gRPC's default
// 4 MiB receive limit, so a client written from the contract alone (with
// default channel arguments) can take it.
#include <gtest/gtest.h>

#include <memory>
#include <string>

#include "hapsim/core/scenes/scene.h"
#include "hapsim/runtime/snapshot_ring.h"
#include "hapsim/streaming/frame_encoder.h"

namespace hapsim::service {
namespace {

constexpr std::size_t kGrpcDefaultReceive_bytes = 4 * 1024 * 1024;

std::size_t KeyframeBytes(const core::SceneSpec& spec) {
  const std::unique_ptr<core::Scene> scene = core::MakeScene(spec);
  const core::MeshTopology& topo = scene->Topology();
  SnapshotRing ring({static_cast<std::size_t>(scene->Vertices_m().cols()), topo.Triangles().Capacity(), 0,
                     topo.Log().Capacity()});
  auto s = ring.Acquire();
  CopyMesh(scene->Vertices_m(), topo, 0, s.get());
  s->part_names = std::make_shared<const std::vector<std::string>>(topo.PartNames());
  s->layer_names = std::make_shared<const std::vector<std::string>>(scene->Status().layer_names);
  TopologyHistory history;
  history.Absorb(*s);
  StreamEncoderState encoder;
  hapsim::v1::Frame frame;
  EncodeFrame(*s, history, &encoder, &frame);
  EXPECT_TRUE(frame.has_keyframe());
  return frame.ByteSizeLong();
}

TEST(KeyframeSize, EverySceneAtItsLargestAcceptedMeshFitsTheDefaultReceiveLimit) {
  const std::pair<const char*, core::SceneSpec> largest[] = {
      {"tissue_block, grid_nodes 101", {"tissue_block", {{"grid_nodes", 101}}}},
      {"acupuncture, patch_grid_nodes 101", {"acupuncture", {{"patch_grid_nodes", 101}}}},
      {"cutting, 10 375 grid nodes", {"cutting", {{"spacing_m", 0.000485}}}},
      // Display vertices = stations x ring x 2 <= nodes (limit 5200).
      {"vessel, dorsal vein 70 mm long, 5076 nodes", {"vessel", {{"length_m", 0.070}}}},
  };
  for (const auto& [what, spec] : largest) {
    const std::size_t bytes = KeyframeBytes(spec);
    EXPECT_LT(bytes, kGrpcDefaultReceive_bytes) << what;
    std::printf("keyframe of %s: %zu bytes\n", what, bytes);
  }
}

}  // namespace
}  // namespace hapsim::service
