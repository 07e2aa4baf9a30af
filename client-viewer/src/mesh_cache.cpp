#include "hapsim/viewer/mesh_cache.h"

#include <cmath>
#include <cstdio>
#include <map>

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
bool Bad(std::string* why, const std::string& text) {
  if (why) *why = text;
  return false;
}

// Edit kinds of TopologyDelta.edits (docs/protocol.md).
enum EditKind : std::uint32_t { kAddVertex = 0, kRemoveVertex = 1, kAddTriangle = 2, kRemoveTriangle = 3 };
constexpr std::uint32_t kMaxSlots = 1u << 26;  // refuse absurd capacities before allocating

// A keyframe's slots once checked: which are live, and how many live
// triangles use each vertex.
struct KeyframeSlots {
  std::vector<std::uint8_t> vertex_live, triangle_live;
  std::vector<std::uint32_t> vertex_uses;
};

// Quantum, array sizes and capacities.
bool CheckKeyframeSizes(const hapsim::v1::Keyframe& key, std::string* why) {
  const double quantum = key.quantum_m();
  if (!(quantum > 0.0 && std::isfinite(quantum))) return Bad(why, "bad quantum");
  if (key.positions_q_size() % 3 != 0) return Bad(why, "positions not a multiple of 3");
  if (key.triangles_size() != 3 * key.triangle_parts_size()) {
    return Bad(why, "triangles and triangle parts do not match");
  }
  const auto n_vertices = static_cast<std::uint32_t>(key.positions_q_size() / 3);
  const auto n_triangles = static_cast<std::uint32_t>(key.triangle_parts_size());
  if (key.vertex_capacity() < n_vertices || key.triangle_capacity() < n_triangles ||
      key.vertex_capacity() > kMaxSlots || key.triangle_capacity() > kMaxSlots) {
    return Bad(why, "slot capacities smaller than the mesh or absurd");
  }
  return true;
}

// Live flags from the free-slot lists: each free slot below the last used one, once.
bool MarkFreeSlots(const hapsim::v1::Keyframe& key, KeyframeSlots* slots, std::string* why) {
  slots->vertex_live.assign(static_cast<std::size_t>(key.positions_q_size() / 3), 1);
  slots->triangle_live.assign(static_cast<std::size_t>(key.triangle_parts_size()), 1);
  for (const auto v : key.free_vertices()) {
    if (v >= slots->vertex_live.size() || !slots->vertex_live[v]) return Bad(why, "bad free vertex slot");
    slots->vertex_live[v] = 0;
  }
  for (const auto t : key.free_triangles()) {
    if (t >= slots->triangle_live.size() || !slots->triangle_live[t]) return Bad(why, "bad free triangle slot");
    slots->triangle_live[t] = 0;
  }
  return true;
}

// Every live triangle names three distinct live vertices and a known part.
bool CountVertexUses(const hapsim::v1::Keyframe& key, KeyframeSlots* slots, std::string* why) {
  const auto n_vertices = static_cast<std::uint32_t>(slots->vertex_live.size());
  const auto& vlive = slots->vertex_live;
  slots->vertex_uses.assign(n_vertices, 0);
  for (std::uint32_t t = 0; t < slots->triangle_live.size(); ++t) {
    if (!slots->triangle_live[t]) continue;
    const std::uint32_t a = key.triangles(static_cast<int>(3 * t)), b = key.triangles(static_cast<int>(3 * t + 1)),
                        c = key.triangles(static_cast<int>(3 * t + 2));
    if (a >= n_vertices || b >= n_vertices || c >= n_vertices || !vlive[a] || !vlive[b] || !vlive[c] || a == b ||
        b == c || a == c) {
      return Bad(why, "triangle " + std::to_string(t) + " names a free, repeated or unknown vertex");
    }
    if (key.triangle_parts(static_cast<int>(t)) >= static_cast<std::uint32_t>(key.part_names_size())) {
      return Bad(why, "triangle " + std::to_string(t) + " has an unknown part");
    }
    ++slots->vertex_uses[a];
    ++slots->vertex_uses[b];
    ++slots->vertex_uses[c];
  }
  return true;
}

// The slots a frame's topology edits touch, laid over the cache's: the
// edits are replayed here first, so a bad edit anywhere refuses the frame
// before anything changes.
class SlotOverlay {
 public:
  SlotOverlay(const MeshCache& cache, const std::vector<std::uint32_t>& cache_uses)
      : cache_(cache), cache_uses_(cache_uses) {}
  bool vertex_live(std::uint32_t v) const {
    const auto it = vlive_.find(v);
    return it != vlive_.end() ? it->second : cache_.vertex_live(v);
  }
  bool triangle_live(std::uint32_t t) const {
    const auto it = tlive_.find(t);
    return it != tlive_.end() ? it->second : cache_.triangle_live(t);
  }
  std::uint32_t& vertex_uses(std::uint32_t v) {
    const auto it = uses_.find(v);
    if (it != uses_.end()) return it->second;
    return uses_[v] = v < cache_uses_.size() ? cache_uses_[v] : 0;
  }
  std::array<std::uint32_t, 3> triangle(std::uint32_t t) const {
    const auto it = tverts_.find(t);
    return it != tverts_.end() ? it->second : cache_.triangle(t);
  }
  void SetVertexLive(std::uint32_t v, bool live) { vlive_[v] = live; }
  void AddTriangle(std::uint32_t t, const std::array<std::uint32_t, 3>& vertices) {
    tlive_[t] = true;
    tverts_[t] = vertices;
    for (const auto v : vertices) ++vertex_uses(v);
  }
  void RemoveTriangle(std::uint32_t t) {
    for (const auto v : triangle(t)) --vertex_uses(v);
    tlive_[t] = false;
  }

 private:
  const MeshCache& cache_;
  const std::vector<std::uint32_t>& cache_uses_;
  std::map<std::uint32_t, bool> vlive_, tlive_;
  std::map<std::uint32_t, std::uint32_t> uses_;
  std::map<std::uint32_t, std::array<std::uint32_t, 3>> tverts_;
};

struct SlotLimits {
  std::uint32_t vertex_capacity, triangle_capacity;
  std::size_t parts;
};

// One edit (`e` points at its kind; an add-triangle edit has all 6 values)
// checked against the overlay, and replayed on it.
bool CheckEdit(const std::uint32_t* e, const SlotLimits& limits, SlotOverlay* o, std::string* why) {
  const std::uint32_t kind = e[0], slot = e[1];
  switch (kind) {
    case kAddVertex:
      if (slot >= limits.vertex_capacity || o->vertex_live(slot))
        return Bad(why, "add of a live or out-of-range vertex slot");
      o->SetVertexLive(slot, true);
      o->vertex_uses(slot) = 0;
      return true;
    case kRemoveVertex:
      if (!o->vertex_live(slot)) return Bad(why, "removal of a free vertex slot");
      if (o->vertex_uses(slot) != 0) return Bad(why, "removal of a vertex a live triangle still uses");
      o->SetVertexLive(slot, false);
      return true;
    case kAddTriangle: {
      const std::uint32_t part = e[2], a = e[3], b = e[4], c = e[5];
      if (slot >= limits.triangle_capacity || o->triangle_live(slot))
        return Bad(why, "add of a live or out-of-range triangle slot");
      if (part >= limits.parts) return Bad(why, "triangle with an unknown part");
      if (!o->vertex_live(a) || !o->vertex_live(b) || !o->vertex_live(c) || a == b || b == c || a == c)
        return Bad(why, "triangle naming a free or repeated vertex");
      o->AddTriangle(slot, {a, b, c});
      return true;
    }
    case kRemoveTriangle:
      if (!o->triangle_live(slot)) return Bad(why, "removal of a free triangle slot");
      o->RemoveTriangle(slot);
      return true;
    default:
      return Bad(why, "unknown edit kind " + std::to_string(kind));
  }
}

// Whether each vertex slot the edits add or remove is live after them.
std::map<std::uint32_t, bool> VerticesLiveAfter(const hapsim::v1::TopologyDelta& topology, std::uint64_t* edits) {
  std::map<std::uint32_t, bool> live_after;
  const auto& e = topology.edits();
  *edits = 0;
  for (int i = 0; i < e.size(); i += (e[i] == kAddTriangle ? 6 : 2), ++*edits) {
    if (e[i] == kAddVertex) live_after[e[i + 1]] = true;
    if (e[i] == kRemoveVertex) live_after[e[i + 1]] = false;
  }
  return live_after;
}

}  // namespace

ApplyResult MeshCache::Apply(const hapsim::v1::Frame& frame, std::string* why) {
  if (frame.has_keyframe()) return ApplyKeyframe(frame, why);
  if (frame.has_delta()) return ApplyDelta(frame, why);
  return Fail(ApplyResult::kMalformed, why, "frame has neither keyframe nor delta");
}

ApplyResult MeshCache::ApplyKeyframe(const hapsim::v1::Frame& frame, std::string* why) {
  const auto& key = frame.keyframe();
  KeyframeSlots slots;
  if (!CheckKeyframeSizes(key, why) || !MarkFreeSlots(key, &slots, why) || !CountVertexUses(key, &slots, why)) {
    return ApplyResult::kMalformed;
  }
  quantum_m_ = key.quantum_m();
  vertex_capacity_ = key.vertex_capacity();
  triangle_capacity_ = key.triangle_capacity();
  q_.assign(key.positions_q().begin(), key.positions_q().end());
  vertex_live_ = std::move(slots.vertex_live);
  vertex_uses_ = std::move(slots.vertex_uses);
  triangle_live_ = std::move(slots.triangle_live);
  const std::size_t n_triangles = triangle_live_.size();
  triangles_.resize(n_triangles);
  triangle_parts_.resize(n_triangles);
  for (std::size_t t = 0; t < n_triangles; ++t) {
    for (std::size_t k = 0; k < 3; ++k) triangles_[t][k] = key.triangles(static_cast<int>(3 * t + k));
    triangle_parts_[t] = static_cast<std::uint16_t>(key.triangle_parts(static_cast<int>(t)));
  }
  live_vertices_ = live_triangles_ = 0;
  for (const auto l : vertex_live_) live_vertices_ += l;
  for (const auto l : triangle_live_) live_triangles_ += l;
  part_names_.assign(key.part_names().begin(), key.part_names().end());
  layer_names_.assign(key.layer_names().begin(), key.layer_names().end());
  topology_version_ = frame.topology_version();
  last_seq_ = frame.seq();
  has_mesh_ = true;
  return ApplyResult::kApplied;
}

bool MeshCache::CheckTopology(const hapsim::v1::TopologyDelta& topo, std::string* why) const {
  SlotOverlay overlay(*this, vertex_uses_);
  const SlotLimits limits{vertex_capacity_, triangle_capacity_, part_names_.size()};
  const auto& e = topo.edits();
  for (int i = 0; i < e.size();) {
    if (i + 2 > e.size()) return Bad(why, "truncated edit");
    const int length = e[i] == kAddTriangle ? 6 : 2;
    if (i + length > e.size()) return Bad(why, "truncated triangle edit");
    if (!CheckEdit(e.data() + i, limits, &overlay, why)) return false;
    i += length;
  }
  return true;
}

void MeshCache::ApplyTopology(const hapsim::v1::TopologyDelta& topo) {
  const auto& e = topo.edits();
  for (int i = 0; i < e.size();) {
    const std::uint32_t kind = e[i], slot = e[i + 1];
    if (kind == kAddVertex) {
      if (slot >= vertex_live_.size()) {
        vertex_live_.resize(slot + 1, 0);
        vertex_uses_.resize(slot + 1, 0);
        q_.resize(3 * (static_cast<std::size_t>(slot) + 1), 0);
      }
      vertex_live_[slot] = 1;
      vertex_uses_[slot] = 0;
      for (int k = 0; k < 3; ++k) q_[3 * slot + static_cast<std::size_t>(k)] = 0;
      ++live_vertices_;
      i += 2;
    } else if (kind == kRemoveVertex) {
      vertex_live_[slot] = 0;
      --live_vertices_;
      i += 2;
    } else if (kind == kAddTriangle) {
      if (slot >= triangle_live_.size()) {
        triangle_live_.resize(slot + 1, 0);
        triangles_.resize(slot + 1, {0, 0, 0});
        triangle_parts_.resize(slot + 1, 0);
      }
      triangle_live_[slot] = 1;
      triangle_parts_[slot] = static_cast<std::uint16_t>(e[i + 2]);
      triangles_[slot] = {e[i + 3], e[i + 4], e[i + 5]};
      for (const auto v : triangles_[slot]) ++vertex_uses_[v];
      ++live_triangles_;
      i += 6;
    } else {  // kRemoveTriangle
      triangle_live_[slot] = 0;
      for (const auto v : triangles_[slot]) --vertex_uses_[v];
      --live_triangles_;
      i += 2;
    }
  }
}

ApplyResult MeshCache::ApplyDelta(const hapsim::v1::Frame& frame, std::string* why) {
  if (!has_mesh_) return Fail(ApplyResult::kNeedKeyframe, why, "delta before any keyframe");
  if (frame.seq() != last_seq_ + 1) {
    return Fail(ApplyResult::kGap, why,
                "expected seq " + std::to_string(last_seq_ + 1) + ", got " + std::to_string(frame.seq()));
  }
  const bool edits = frame.has_topology();
  const std::uint64_t from = edits ? frame.topology().from_version() : frame.topology_version();
  if (from != topology_version_) {
    return Fail(ApplyResult::kTopologyMismatch, why,
                "delta for topology " + std::to_string(from) + ", cache holds " + std::to_string(topology_version_));
  }
  if (edits && !CheckTopology(frame.topology(), why)) return ApplyResult::kMalformed;
  if (!CheckMovedVertices(frame, why)) return ApplyResult::kMalformed;
  if (edits) ApplyTopology(frame.topology());
  MoveVertices(frame.delta());
  topology_version_ = frame.topology_version();
  last_seq_ = frame.seq();
  return ApplyResult::kApplied;
}

// The delta's indices into scratch_indices_, each checked against the mesh
// as it will be once the edits are in (a vertex the edits add beyond the
// current slots is live afterwards).
bool MeshCache::CheckMovedVertices(const hapsim::v1::Frame& frame, std::string* why) {
  const auto& d = frame.delta();
  if (d.position_dq_size() != 3 * d.index_gaps_size()) return Bad(why, "delta needs 3 position values per index");
  std::map<std::uint32_t, bool> live_after;
  if (frame.has_topology()) {
    std::uint64_t count = 0;
    live_after = VerticesLiveAfter(frame.topology(), &count);
    // One edit per topology version: a frame that skips or repeats
    // versions would leave the cache out of step with the server.
    const std::uint64_t from = frame.topology().from_version();
    if (frame.topology_version() != from + count) {
      return Bad(why, std::to_string(count) + " edits do not lead from topology " + std::to_string(from) + " to " +
                          std::to_string(frame.topology_version()));
    }
  }
  scratch_indices_.clear();
  std::uint64_t index = 0;
  for (int i = 0; i < d.index_gaps_size(); ++i) {
    index = i == 0 ? d.index_gaps(0) : index + d.index_gaps(i);
    const auto it = index < kMaxSlots ? live_after.find(static_cast<std::uint32_t>(index)) : live_after.end();
    const bool live = it != live_after.end() ? it->second : vertex_live(index);
    if ((i > 0 && d.index_gaps(i) == 0) || !live) return Bad(why, "delta vertex index not live, or not increasing");
    scratch_indices_.push_back(static_cast<std::uint32_t>(index));
  }
  return true;
}

void MeshCache::MoveVertices(const hapsim::v1::MeshDelta& d) {
  for (std::size_t i = 0; i < scratch_indices_.size(); ++i) {
    for (std::size_t k = 0; k < 3; ++k) {
      std::int32_t& q = q_[3 * scratch_indices_[i] + k];
      // Modular add: the encoder's narrowed 64-bit difference round-trips exactly.
      q = static_cast<std::int32_t>(static_cast<std::uint32_t>(q) +
                                    static_cast<std::uint32_t>(d.position_dq(static_cast<int>(3 * i + k))));
    }
  }
}

Eigen::Matrix3Xd MeshCache::Vertices_m() const {
  Eigen::Matrix3Xd v(3, static_cast<Eigen::Index>(vertex_slots()));
  for (std::size_t i = 0; i < q_.size(); ++i) {
    v(static_cast<Eigen::Index>(i % 3), static_cast<Eigen::Index>(i / 3)) = q_[i] * quantum_m_;
  }
  return v;
}

CompactMesh MeshCache::Compact() const {
  CompactMesh out;
  std::vector<std::uint32_t> index_of(vertex_slots(), 0);
  out.vertices_m.resize(3, static_cast<Eigen::Index>(live_vertices_));
  Eigen::Index n = 0;
  for (std::size_t v = 0; v < vertex_slots(); ++v) {
    if (!vertex_live_[v]) continue;
    index_of[v] = static_cast<std::uint32_t>(n);
    for (int k = 0; k < 3; ++k) out.vertices_m(k, n) = q_[3 * v + static_cast<std::size_t>(k)] * quantum_m_;
    ++n;
  }
  for (std::size_t t = 0; t < triangle_slots(); ++t) {
    if (!triangle_live_[t]) continue;
    for (const auto v : triangles_[t]) out.triangles.push_back(index_of[v]);
    out.triangle_parts.push_back(triangle_parts_[t]);
  }
  out.part_names = part_names_;
  return out;
}

bool WriteObj(const std::string& path, const CompactMesh& mesh, const std::string& comment) {
  std::FILE* f = std::fopen(path.c_str(), "w");
  if (!f) return false;
  std::fprintf(f, "# %s\n# units: metres\n", comment.c_str());
  const Eigen::Matrix3Xd& v = mesh.vertices_m;
  for (Eigen::Index i = 0; i < v.cols(); ++i) std::fprintf(f, "v %.9g %.9g %.9g\n", v(0, i), v(1, i), v(2, i));
  const std::size_t groups = std::max<std::size_t>(mesh.part_names.size(), 1);
  for (std::size_t part = 0; part < groups; ++part) {
    std::fprintf(f, "o %s\n", mesh.part_names.empty() ? "mesh" : mesh.part_names[part].c_str());
    for (std::size_t t = 0; t < mesh.triangles.size() / 3; ++t) {
      if (!mesh.part_names.empty() && (t >= mesh.triangle_parts.size() || mesh.triangle_parts[t] != part)) continue;
      std::fprintf(f, "f %u %u %u\n", mesh.triangles[3 * t] + 1, mesh.triangles[3 * t + 1] + 1,
                   mesh.triangles[3 * t + 2] + 1);
    }
  }
  return std::fclose(f) == 0;
}

}  // namespace hapsim::viewer
