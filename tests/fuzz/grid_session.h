// The server side of a small cut-ready session, for the stream fuzz targets:
// a 6 x 6 grid of "skin" (48 vertex and 72 triangle slots, so a cut has room
// to add), publishing snapshots as Session::PublishSnapshot does and taking
// them into a TopologyHistory as ViewerHub::Pump does (the history's End()
// is the version the session is told the pump has taken).
#pragma once
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "hapsim/core/mesh/mesh_topology.h"
#include "hapsim/runtime/snapshot_ring.h"
#include "hapsim/streaming/topology_history.h"

namespace hapsim::fuzz {

struct GridSession {
  static constexpr std::uint32_t kSide = 6, kVertexSlots = 48, kTriangleSlots = 72;

  Eigen::Matrix3Xd x_m;
  core::MeshTopology topology;
  service::SnapshotRing ring;
  service::TopologyHistory history;
  std::shared_ptr<const std::vector<std::string>> part_names;
  std::uint64_t id = 0;

  // log_capacity: the scene's topology log; history_capacity: the pump's.
  // Small ones make a burst of edits outrun them (viewers then get keyframes).
  explicit GridSession(std::size_t log_capacity = 256, std::size_t history_capacity = 1 << 16)
      : x_m(Eigen::Matrix3Xd::Zero(3, kVertexSlots)),
        topology({.vertex_capacity = kVertexSlots,
                  .triangle_capacity = kTriangleSlots,
                  .part_names = {"skin", "wound"},
                  .log_capacity = log_capacity}),
        ring({kVertexSlots, kTriangleSlots, 0, log_capacity}),
        history(history_capacity) {
    for (std::uint32_t i = 0; i < kSide; ++i)
      for (std::uint32_t j = 0; j < kSide; ++j) x_m.col(topology.AddVertex()) = Eigen::Vector3d(i * 0.003, j * 0.003, 0.0);
    for (std::uint32_t i = 0; i + 1 < kSide; ++i)
      for (std::uint32_t j = 0; j + 1 < kSide; ++j) {
        const std::uint32_t a = i * kSide + j, b = a + 1, c = a + kSide, d = c + 1;
        topology.AddTriangle(a, c, b, 0);
        topology.AddTriangle(b, c, d, 0);
      }
    topology.Seal();
    part_names = std::make_shared<const std::vector<std::string>>(topology.PartNames());
  }

  // A snapshot of the mesh as it is now (edits since what the history has
  // taken), as a tick publishes it; nullptr when every ring buffer is still
  // held (the session skips one). The pump takes it with history.Absorb.
  std::shared_ptr<const service::SceneSnapshot> Publish() {
    std::shared_ptr<service::SceneSnapshot> s = ring.Acquire();
    if (!s) return nullptr;
    service::CopyMesh(x_m, topology, history.End(), s.get());
    s->id = ++id;
    s->part_names = part_names;
    return s;
  }
};

}  // namespace hapsim::fuzz
