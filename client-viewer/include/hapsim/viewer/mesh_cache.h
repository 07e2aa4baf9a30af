// The viewer's copy of a session's mesh, rebuilt from the Frame stream: a
// keyframe replaces it, a delta moves the listed vertices. A delta is applied
// only if it is the very next seq of the stream and names the same topology
// version; otherwise the cache refuses it and the client resubscribes for a
// keyframe. A malformed frame is refused whole: the cache never half-applies.
#pragma once
#include <cstdint>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "hapsim/v1/viewer.pb.h"

namespace hapsim::viewer {

enum class ApplyResult { kApplied, kNeedKeyframe, kGap, kTopologyMismatch, kMalformed };
const char* ToString(ApplyResult r);

struct Part {
  std::string name;
  std::uint32_t first_triangle = 0, triangle_count = 0;
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
  std::size_t vertex_count() const { return q_.size() / 3; }
  const std::vector<std::uint32_t>& triangles() const { return triangles_; }
  const std::vector<Part>& parts() const { return parts_; }
  const std::vector<std::string>& layer_names() const { return layer_names_; }
  Eigen::Matrix3Xd Vertices_m() const;  // q * quantum

 private:
  ApplyResult ApplyKeyframe(const hapsim::v1::Frame& frame, std::string* why);
  ApplyResult ApplyDelta(const hapsim::v1::Frame& frame, std::string* why);

  bool has_mesh_ = false;
  std::uint64_t last_seq_ = 0;
  std::uint64_t topology_version_ = 0;
  double quantum_m_ = 0.0;
  std::vector<std::int32_t> q_;  // 3 per vertex
  std::vector<std::uint32_t> triangles_;
  std::vector<Part> parts_;
  std::vector<std::string> layer_names_;
  std::vector<std::uint32_t> scratch_indices_;
};

// Writes the mesh as Wavefront OBJ, one "o" group per part, positions in m.
bool WriteObj(const std::string& path, const Eigen::Matrix3Xd& vertices_m, const std::vector<std::uint32_t>& triangles,
              const std::vector<Part>& parts, const std::string& comment);

}  // namespace hapsim::viewer
