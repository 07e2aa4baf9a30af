#include "hapsim/viewer/mesh_cache.h"

#include <cmath>
#include <cstdio>

namespace hapsim::viewer {

const char* ToString(ApplyResult r) {
  switch (r) {
    case ApplyResult::kApplied: return "applied";
    case ApplyResult::kNeedKeyframe: return "need keyframe";
    case ApplyResult::kGap: return "seq gap";
    case ApplyResult::kTopologyMismatch: return "topology mismatch";
    case ApplyResult::kMalformed: return "malformed frame";
  }
  return "unknown";
}

namespace {
ApplyResult Fail(ApplyResult r, std::string* why, const std::string& text) {
  if (why) *why = text;
  return r;
}
}  // namespace

ApplyResult MeshCache::Apply(const hapsim::v1::Frame& frame, std::string* why) {
  if (frame.has_keyframe()) return ApplyKeyframe(frame, why);
  if (frame.has_delta()) return ApplyDelta(frame, why);
  return Fail(ApplyResult::kMalformed, why, "frame has neither keyframe nor delta");
}

ApplyResult MeshCache::ApplyKeyframe(const hapsim::v1::Frame& frame, std::string* why) {
  const auto& key = frame.keyframe();
  const double quantum = key.quantum_m();
  if (!(quantum > 0.0 && std::isfinite(quantum))) return Fail(ApplyResult::kMalformed, why, "bad quantum");
  if (key.positions_q_size() % 3 != 0) return Fail(ApplyResult::kMalformed, why, "positions not a multiple of 3");
  if (key.triangles_size() % 3 != 0) return Fail(ApplyResult::kMalformed, why, "triangles not a multiple of 3");
  const auto n_vertices = static_cast<std::uint32_t>(key.positions_q_size() / 3);
  for (const auto index : key.triangles()) {
    if (index >= n_vertices) return Fail(ApplyResult::kMalformed, why, "triangle index out of range");
  }
  const auto n_triangles = static_cast<std::uint64_t>(key.triangles_size() / 3);
  for (const auto& p : key.parts()) {
    if (static_cast<std::uint64_t>(p.first_triangle()) + p.triangle_count() > n_triangles) {
      return Fail(ApplyResult::kMalformed, why, "part '" + p.name() + "' runs past the triangle list");
    }
  }
  quantum_m_ = quantum;
  q_.assign(key.positions_q().begin(), key.positions_q().end());
  triangles_.assign(key.triangles().begin(), key.triangles().end());
  parts_.clear();
  for (const auto& p : key.parts()) parts_.push_back({p.name(), p.first_triangle(), p.triangle_count()});
  layer_names_.assign(key.layer_names().begin(), key.layer_names().end());
  topology_version_ = frame.topology_version();
  last_seq_ = frame.seq();
  has_mesh_ = true;
  return ApplyResult::kApplied;
}

ApplyResult MeshCache::ApplyDelta(const hapsim::v1::Frame& frame, std::string* why) {
  if (!has_mesh_) return Fail(ApplyResult::kNeedKeyframe, why, "delta before any keyframe");
  if (frame.seq() != last_seq_ + 1) {
    return Fail(ApplyResult::kGap, why,
                "expected seq " + std::to_string(last_seq_ + 1) + ", got " + std::to_string(frame.seq()));
  }
  if (frame.topology_version() != topology_version_) {
    return Fail(ApplyResult::kTopologyMismatch, why,
                "delta for topology " + std::to_string(frame.topology_version()) + ", cache holds " +
                    std::to_string(topology_version_));
  }
  const auto& d = frame.delta();
  if (d.position_dq_size() != 3 * d.index_gaps_size()) {
    return Fail(ApplyResult::kMalformed, why, "delta needs 3 position values per index");
  }
  // Validate every index before touching the mesh.
  scratch_indices_.clear();
  std::uint64_t index = 0;
  for (int i = 0; i < d.index_gaps_size(); ++i) {
    index = i == 0 ? d.index_gaps(0) : index + d.index_gaps(i);
    if ((i > 0 && d.index_gaps(i) == 0) || index >= vertex_count()) {
      return Fail(ApplyResult::kMalformed, why, "delta vertex index out of range or not increasing");
    }
    scratch_indices_.push_back(static_cast<std::uint32_t>(index));
  }
  for (std::size_t i = 0; i < scratch_indices_.size(); ++i) {
    for (int k = 0; k < 3; ++k) {
      std::int32_t& q = q_[3 * scratch_indices_[i] + static_cast<std::size_t>(k)];
      // Modular add: the encoder's narrowed 64-bit difference round-trips exactly.
      q = static_cast<std::int32_t>(static_cast<std::uint32_t>(q) +
                                    static_cast<std::uint32_t>(d.position_dq(static_cast<int>(3 * i) + k)));
    }
  }
  last_seq_ = frame.seq();
  return ApplyResult::kApplied;
}

Eigen::Matrix3Xd MeshCache::Vertices_m() const {
  Eigen::Matrix3Xd v(3, static_cast<Eigen::Index>(vertex_count()));
  for (std::size_t i = 0; i < q_.size(); ++i) {
    v(static_cast<Eigen::Index>(i % 3), static_cast<Eigen::Index>(i / 3)) = q_[i] * quantum_m_;
  }
  return v;
}

bool WriteObj(const std::string& path, const Eigen::Matrix3Xd& v, const std::vector<std::uint32_t>& triangles,
              const std::vector<Part>& parts, const std::string& comment) {
  std::FILE* f = std::fopen(path.c_str(), "w");
  if (!f) return false;
  std::fprintf(f, "# %s\n# units: metres\n", comment.c_str());
  for (Eigen::Index i = 0; i < v.cols(); ++i) std::fprintf(f, "v %.9g %.9g %.9g\n", v(0, i), v(1, i), v(2, i));
  std::vector<Part> groups = parts;
  if (groups.empty()) groups.push_back({"mesh", 0, static_cast<std::uint32_t>(triangles.size() / 3)});
  for (const auto& p : groups) {
    std::fprintf(f, "o %s\n", p.name.c_str());
    for (std::uint32_t t = p.first_triangle; t < p.first_triangle + p.triangle_count && 3 * t + 2 < triangles.size(); ++t) {
      std::fprintf(f, "f %u %u %u\n", triangles[3 * t] + 1, triangles[3 * t + 1] + 1, triangles[3 * t + 2] + 1);
    }
  }
  return std::fclose(f) == 0;
}

}  // namespace hapsim::viewer
