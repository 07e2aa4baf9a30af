// The connectivity of a scene's displayed mesh, in stable slots (slot_pool.h):
// vertex slots (their positions are the scene's Vertices_m() columns),
// triangle slots holding three vertex slots and a part (an index into the
// part names: "skin", "needle", ...), and the log of every edit
// (topology_log.h) from which viewers are updated incrementally.
//
// Invariants: a live triangle references three distinct live vertices; a
// vertex referenced by a live triangle cannot be removed. Capacities are
// fixed at construction: after it, nothing allocates or throws — a full
// pool answers kNoSlot and is counted in CapacityFailures(); using a dead
// slot is a programming error (HAPSIM_DEMAND).
#pragma once
#include <array>
#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include "hapsim/core/mesh/slot_pool.h"
#include "hapsim/core/mesh/topology_log.h"

namespace hapsim::core {

struct MeshTopologyDef {
  std::uint32_t vertex_capacity = 0;
  std::uint32_t triangle_capacity = 0;
  std::vector<std::string> part_names;  // at most 65535
  std::size_t log_capacity = 4096;      // edits kept for incremental viewer updates
  // Triangles each vertex's incidence list holds (0: none kept). With it,
  // edge lookups are O(valence); AddTriangle fails (kNoSlot, counted) at a
  // vertex whose list is full.
  std::uint32_t max_vertex_triangles = 0;
};

class MeshTopology {
 public:
  MeshTopology() : MeshTopology(MeshTopologyDef{}) {}
  explicit MeshTopology(const MeshTopologyDef& def);  // throws std::invalid_argument on a bad def

  std::uint32_t AddVertex();                 // a new vertex slot, or kNoSlot when full
  bool RemoveVertex(std::uint32_t vertex);   // false (and nothing done) while a live triangle uses it
  // A triangle of three distinct live vertices; kNoSlot when full.
  std::uint32_t AddTriangle(std::uint32_t a, std::uint32_t b, std::uint32_t c, std::uint16_t part);
  void RemoveTriangle(std::uint32_t triangle);

  // The current topology becomes the initial one (end of a scene's build):
  // Reset() returns to it. Restarts the log.
  void Seal();
  // Back to the sealed topology; the log restarts (viewers get a keyframe).
  void Reset();

  const SlotPool& Vertices() const { return vertices_; }
  const SlotPool& Triangles() const { return triangles_; }
  const std::array<std::uint32_t, 3>& TriangleVertices(std::uint32_t t) const { return tri_vertices_[t]; }
  std::uint16_t TrianglePart(std::uint32_t t) const { return tri_part_[t]; }
  const std::vector<std::array<std::uint32_t, 3>>& TriangleVertexArray() const { return tri_vertices_; }  // (capacity)
  const std::vector<std::uint16_t>& TrianglePartArray() const { return tri_part_; }                     // (capacity)
  std::uint32_t VertexUses(std::uint32_t v) const { return vertex_refs_[v]; }  // live triangles using v
  const std::vector<std::string>& PartNames() const { return part_names_; }

  // With MeshTopologyDef::max_vertex_triangles > 0: the live triangles using
  // vertex v, and the live triangle holding the directed edge a -> b in its
  // counter-clockwise order (kNoSlot if none). O(valence).
  std::span<const std::uint32_t> TrianglesOf(std::uint32_t v) const {
    if (max_vertex_triangles_ == 0) return {};
    return {vertex_triangles_.data() + static_cast<std::size_t>(v) * max_vertex_triangles_, vertex_refs_[v]};
  }
  std::uint32_t TriangleWithEdge(std::uint32_t a, std::uint32_t b) const;
  const TopologyLog& Log() const { return log_; }
  std::uint64_t Version() const { return log_.Version(); }
  std::uint64_t CapacityFailures() const { return capacity_failures_; }

  // Live triangles as a flat index list (3 per triangle, slot order) and
  // their parts. Allocates: for tests, exports and validation, not a step.
  std::vector<std::uint32_t> LiveTriangleIndices(std::vector<std::uint16_t>* parts = nullptr) const;

 private:
  struct Sealed;

  SlotPool vertices_, triangles_;
  std::vector<std::array<std::uint32_t, 3>> tri_vertices_;  // (triangle capacity)
  std::vector<std::uint16_t> tri_part_;                     // (triangle capacity)
  std::vector<std::uint32_t> vertex_refs_;                  // (vertex capacity) live triangles using each vertex
  std::uint32_t max_vertex_triangles_ = 0;
  std::vector<std::uint32_t> vertex_triangles_;             // (vertex capacity x max_vertex_triangles_)
  std::vector<std::string> part_names_;
  TopologyLog log_;
  std::uint64_t capacity_failures_ = 0;
  // The sealed (initial) topology, restored by Reset() without allocating.
  SlotPool sealed_vertices_, sealed_triangles_;
  std::vector<std::array<std::uint32_t, 3>> sealed_tri_vertices_;
  std::vector<std::uint16_t> sealed_tri_part_;
  std::vector<std::uint32_t> sealed_vertex_refs_;
  std::vector<std::uint32_t> sealed_vertex_triangles_;
};

}  // namespace hapsim::core
