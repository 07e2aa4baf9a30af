// The viewer's copy of a session's mesh, rebuilt from the Frame stream. The
// mesh lives in stable slots like the server's: a keyframe replaces it; a
// delta frame first applies its topology edits (vertices and triangles added
// or removed, by slot) and then moves the listed vertices. A delta is
// applied only if it is the very next seq of the stream and starts from the
// topology version the cache holds; otherwise the cache refuses it and the
// client resubscribes for a keyframe. A malformed frame is refused whole:
// every edit and index is checked before anything changes, so the cache
// never half-applies a frame. Invariants kept: a live triangle names three
// distinct live vertices; a vertex in use by a live triangle is not removed.
#pragma once
#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "hapsim/v1/viewer.pb.h"

namespace hapsim::viewer {

enum class ApplyResult { kApplied, kNeedKeyframe, kGap, kTopologyMismatch, kMalformed };
const char* ToString(ApplyResult r);

// A mesh with only its live elements, vertices renumbered 0..n-1.
struct CompactMesh {
  Eigen::Matrix3Xd vertices_m;               // 3 x live vertices [m]
  std::vector<std::uint32_t> triangles;      // 3 per live triangle
  std::vector<std::uint16_t> triangle_parts; // 1 per live triangle: index into part_names
  std::vector<std::string> part_names;
};

class MeshCache {
 public:
  ApplyResult Apply(const hapsim::v1::Frame& frame, std::string* why = nullptr);
  // Forget the mesh (e.g. before resubscribing): the next frame must be a keyframe.
  void Invalidate() { has_mesh_ = false; }

  bool has_mesh() const { return has_mesh_; }
  std::uint64_t last_seq() const { return last_seq_; }
  std::uint64_t topology_version() const { return topology_version_; }
  double quantum_m() const { return quantum_m_; }
  std::size_t vertex_slots() const { return vertex_live_.size(); }
  std::size_t triangle_slots() const { return triangle_live_.size(); }
  bool vertex_live(std::size_t v) const { return v < vertex_live_.size() && vertex_live_[v]; }
  bool triangle_live(std::size_t t) const { return t < triangle_live_.size() && triangle_live_[t]; }
  const std::array<std::uint32_t, 3>& triangle(std::size_t t) const { return triangles_[t]; }
  std::uint16_t triangle_part(std::size_t t) const { return triangle_parts_[t]; }
  std::size_t live_vertex_count() const { return live_vertices_; }
  std::size_t live_triangle_count() const { return live_triangles_; }
  const std::vector<std::string>& part_names() const { return part_names_; }
  const std::vector<std::string>& layer_names() const { return layer_names_; }
  // Quantised position of every vertex slot, 3 per slot (p_m = q * quantum_m;
  // free slots hold their last value): read in place by a viewer that
  // converts it straight into what it draws.
  const std::vector<std::int32_t>& positions_q() const { return q_; }
  // Position of every vertex slot (q * quantum; free slots hold their last value).
  Eigen::Matrix3Xd Vertices_m() const;
  CompactMesh Compact() const;

 private:
  ApplyResult ApplyKeyframe(const hapsim::v1::Frame& frame, std::string* why);
  ApplyResult ApplyDelta(const hapsim::v1::Frame& frame, std::string* why);
  bool CheckTopology(const hapsim::v1::TopologyDelta& topology, std::string* why) const;
  bool CheckMovedVertices(const hapsim::v1::Frame& frame, std::string* why);  // fills scratch_indices_
  void ApplyTopology(const hapsim::v1::TopologyDelta& topology);
  void MoveVertices(const hapsim::v1::MeshDelta& delta);  // the vertices in scratch_indices_

  bool has_mesh_ = false;
  std::uint64_t last_seq_ = 0;
  std::uint64_t topology_version_ = 0;
  double quantum_m_ = 0.0;
  std::uint32_t vertex_capacity_ = 0, triangle_capacity_ = 0;
  std::vector<std::int32_t> q_;                          // 3 per vertex slot
  std::vector<std::uint8_t> vertex_live_;                // per vertex slot
  std::vector<std::uint32_t> vertex_uses_;               // live triangles naming each vertex slot
  std::vector<std::array<std::uint32_t, 3>> triangles_;  // per triangle slot
  std::vector<std::uint16_t> triangle_parts_;            // per triangle slot
  std::vector<std::uint8_t> triangle_live_;              // per triangle slot
  std::size_t live_vertices_ = 0, live_triangles_ = 0;
  std::vector<std::string> part_names_;
  std::vector<std::string> layer_names_;
  std::vector<std::uint32_t> scratch_indices_;
};

// Writes the mesh as Wavefront OBJ, one "o" group per part, positions in m.
bool WriteObj(const std::string& path, const CompactMesh& mesh, const std::string& comment);

}  // namespace hapsim::viewer
