#include "hapsim/core/mesh/mesh_topology.h"

#include <algorithm>
#include <stdexcept>

#include "hapsim/core/assert.h"

namespace hapsim::core {

MeshTopology::MeshTopology(const MeshTopologyDef& def)
    : vertices_(def.vertex_capacity),
      triangles_(def.triangle_capacity),
      tri_vertices_(def.triangle_capacity, std::array<std::uint32_t, 3>{0, 0, 0}),
      tri_part_(def.triangle_capacity, 0),
      vertex_refs_(def.vertex_capacity, 0),
      max_vertex_triangles_(def.max_vertex_triangles),
      vertex_triangles_(static_cast<std::size_t>(def.vertex_capacity) * def.max_vertex_triangles, kNoSlot),
      part_names_(def.part_names),
      log_(def.log_capacity),
      sealed_vertices_(def.vertex_capacity),
      sealed_triangles_(def.triangle_capacity),
      sealed_tri_vertices_(tri_vertices_),
      sealed_tri_part_(tri_part_),
      sealed_vertex_refs_(vertex_refs_),
      sealed_vertex_triangles_(vertex_triangles_) {
  if (part_names_.size() > 0xffff) throw std::invalid_argument("MeshTopology: more than 65535 parts");
  if (def.vertex_capacity == kNoSlot || def.triangle_capacity == kNoSlot)
    throw std::invalid_argument("MeshTopology: capacity too large");
}

std::uint32_t MeshTopology::AddVertex() {
  const std::uint32_t v = vertices_.Alloc();
  if (v == kNoSlot) {
    ++capacity_failures_;
    return kNoSlot;
  }
  vertex_refs_[v] = 0;
  log_.Push({TopologyEdit::Kind::kAddVertex, 0, v, {}});
  return v;
}

bool MeshTopology::RemoveVertex(std::uint32_t v) {
  HAPSIM_DEMAND(vertices_.IsLive(v), "MeshTopology::RemoveVertex: the vertex is not live");
  if (vertex_refs_[v] != 0) return false;
  vertices_.Free(v);
  log_.Push({TopologyEdit::Kind::kRemoveVertex, 0, v, {}});
  return true;
}

std::uint32_t MeshTopology::AddTriangle(std::uint32_t a, std::uint32_t b, std::uint32_t c, std::uint16_t part) {
  HAPSIM_DEMAND(vertices_.IsLive(a) && vertices_.IsLive(b) && vertices_.IsLive(c),
                "MeshTopology::AddTriangle: a vertex is not live");
  HAPSIM_DEMAND(a != b && b != c && a != c, "MeshTopology::AddTriangle: vertices must be distinct");
  HAPSIM_DEMAND(part < part_names_.size(), "MeshTopology::AddTriangle: no such part");
  const bool lists_full = max_vertex_triangles_ > 0 &&
                         (vertex_refs_[a] >= max_vertex_triangles_ || vertex_refs_[b] >= max_vertex_triangles_ ||
                          vertex_refs_[c] >= max_vertex_triangles_);
  const std::uint32_t t = lists_full ? kNoSlot : triangles_.Alloc();
  if (t == kNoSlot) {
    ++capacity_failures_;
    return kNoSlot;
  }
  tri_vertices_[t] = {a, b, c};
  tri_part_[t] = part;
  for (const std::uint32_t v : {a, b, c}) {
    if (max_vertex_triangles_ > 0) vertex_triangles_[static_cast<std::size_t>(v) * max_vertex_triangles_ + vertex_refs_[v]] = t;
    ++vertex_refs_[v];
  }
  log_.Push({TopologyEdit::Kind::kAddTriangle, part, t, {a, b, c}});
  return t;
}

void MeshTopology::RemoveTriangle(std::uint32_t t) {
  HAPSIM_DEMAND(triangles_.IsLive(t), "MeshTopology::RemoveTriangle: the triangle is not live");
  triangles_.Free(t);
  for (const std::uint32_t v : tri_vertices_[t]) {
    if (max_vertex_triangles_ > 0) {  // swap-remove t from v's list
      std::uint32_t* list = &vertex_triangles_[static_cast<std::size_t>(v) * max_vertex_triangles_];
      for (std::uint32_t k = 0; k < vertex_refs_[v]; ++k) {
        if (list[k] != t) continue;
        list[k] = list[vertex_refs_[v] - 1];
        list[vertex_refs_[v] - 1] = kNoSlot;
        break;
      }
    }
    --vertex_refs_[v];
  }
  log_.Push({TopologyEdit::Kind::kRemoveTriangle, 0, t, {}});
}

void MeshTopology::Seal() {
  sealed_vertices_.CopyFrom(vertices_);
  sealed_triangles_.CopyFrom(triangles_);
  std::copy(tri_vertices_.begin(), tri_vertices_.end(), sealed_tri_vertices_.begin());
  std::copy(tri_part_.begin(), tri_part_.end(), sealed_tri_part_.begin());
  std::copy(vertex_refs_.begin(), vertex_refs_.end(), sealed_vertex_refs_.begin());
  std::copy(vertex_triangles_.begin(), vertex_triangles_.end(), sealed_vertex_triangles_.begin());
  log_.Restart();
}

void MeshTopology::Reset() {
  vertices_.CopyFrom(sealed_vertices_);
  triangles_.CopyFrom(sealed_triangles_);
  std::copy(sealed_tri_vertices_.begin(), sealed_tri_vertices_.end(), tri_vertices_.begin());
  std::copy(sealed_tri_part_.begin(), sealed_tri_part_.end(), tri_part_.begin());
  std::copy(sealed_vertex_refs_.begin(), sealed_vertex_refs_.end(), vertex_refs_.begin());
  std::copy(sealed_vertex_triangles_.begin(), sealed_vertex_triangles_.end(), vertex_triangles_.begin());
  log_.Restart();
}

std::uint32_t MeshTopology::TriangleWithEdge(std::uint32_t a, std::uint32_t b) const {
  HAPSIM_DEMAND(max_vertex_triangles_ > 0, "MeshTopology::TriangleWithEdge needs max_vertex_triangles > 0");
  for (const std::uint32_t t : TrianglesOf(a)) {
    const auto& v = tri_vertices_[t];
    for (int k = 0; k < 3; ++k) {
      if (v[static_cast<std::size_t>(k)] == a && v[static_cast<std::size_t>((k + 1) % 3)] == b) return t;
    }
  }
  return kNoSlot;
}

std::vector<std::uint32_t> MeshTopology::LiveTriangleIndices(std::vector<std::uint16_t>* parts) const {
  std::vector<std::uint32_t> out;
  if (parts) parts->clear();
  for (std::uint32_t t = 0; t < triangles_.HighWater(); ++t) {
    if (!triangles_.IsLive(t)) continue;
    out.insert(out.end(), tri_vertices_[t].begin(), tri_vertices_[t].end());
    if (parts) parts->push_back(tri_part_[t]);
  }
  return out;
}

}  // namespace hapsim::core
