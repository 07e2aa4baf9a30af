#include "hapsim/runtime/scene_snapshot.h"

#include <algorithm>

namespace hapsim::service {

void CopyMesh(const Eigen::Matrix3Xd& vertices_m, const core::MeshTopology& topo, std::uint64_t taken_version,
              SceneSnapshot* s) {
  s->vertices_m = vertices_m;  // same size as the buffer: no allocation
  s->vertex_slots = topo.Vertices().HighWater();
  s->triangle_slots = topo.Triangles().HighWater();
  s->topology_version = topo.Version();
  if (s->topology_arrays_version != s->topology_version) {
    const auto& vlive = topo.Vertices().LiveFlags();
    std::copy(vlive.begin(), vlive.end(), s->vertex_live.begin());
    const auto& tlive = topo.Triangles().LiveFlags();
    std::copy(tlive.begin(), tlive.end(), s->triangle_live.begin());
    std::copy(topo.TriangleVertexArray().begin(), topo.TriangleVertexArray().end(), s->triangles.begin());
    std::copy(topo.TrianglePartArray().begin(), topo.TrianglePartArray().end(), s->triangle_parts.begin());
    s->topology_arrays_version = s->topology_version;
  }
  const core::TopologyLog& log = topo.Log();
  s->edits_from_version = std::max(taken_version, log.Oldest());
  s->topology_edits.clear();  // capacity reserved to the log's: no allocation
  for (std::uint64_t v = s->edits_from_version; v < log.Version(); ++v) s->topology_edits.push_back(log.At(v));
}

double PeakForceSince(const SceneSnapshot& s, std::uint64_t previous_id) {
  constexpr std::uint64_t n = SceneSnapshot::kPeakIntervals;
  std::uint64_t first = previous_id == 0 || previous_id >= s.id ? s.id : previous_id + 1;
  if (s.id - first >= n) first = s.id - n + 1;
  double peak = 0.0;
  for (std::uint64_t k = first; k <= s.id; ++k) peak = std::max(peak, s.interval_peak_N[k % n]);
  return peak;
}

}  // namespace hapsim::service
