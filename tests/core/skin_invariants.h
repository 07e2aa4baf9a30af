// Every invariant the skin cutter promises, checked from the outside: the
// first violation as text ("" when all hold). Shared by the cutter's and the
// cutting scene's tests.
#pragma once
#include <algorithm>
#include <array>
#include <cmath>
#include <map>
#include <string>
#include <vector>

#include <Eigen/Geometry>

#include "hapsim/core/cutting/skin_mesh.h"

namespace hapsim::core::test {

inline double SignedRestArea(const SkinMesh& s, std::uint32_t t) {
  const auto& v = s.topology.TriangleVertices(t);
  const Eigen::Vector3d a = s.model.x0_m.col(v[0]), b = s.model.x0_m.col(v[1]), c = s.model.x0_m.col(v[2]);
  return 0.5 * (b - a).cross(c - a).z();
}

// Two triangles' interiors overlap (separating axis test, rest plane).
inline bool InteriorsOverlap(const std::array<Eigen::Vector2d, 3>& t1, const std::array<Eigen::Vector2d, 3>& t2) {
  for (const auto* t : {&t1, &t2}) {
    for (int k = 0; k < 3; ++k) {
      const Eigen::Vector2d e = (*t)[static_cast<std::size_t>((k + 1) % 3)] - (*t)[static_cast<std::size_t>(k)];
      const Eigen::Vector2d axis(-e.y(), e.x());
      double lo1 = 1e9, hi1 = -1e9, lo2 = 1e9, hi2 = -1e9;
      for (const auto& p : t1) lo1 = std::min(lo1, p.dot(axis)), hi1 = std::max(hi1, p.dot(axis));
      for (const auto& p : t2) lo2 = std::min(lo2, p.dot(axis)), hi2 = std::max(hi2, p.dot(axis));
      const double slack = 1e-9 * axis.squaredNorm();  // touching along an edge is not overlapping
      if (hi1 <= lo2 + slack || hi2 <= lo1 + slack) return false;
    }
  }
  return true;
}

// The first pair of live triangles whose interiors overlap at rest (cells of
// one spacing bucket the candidates).
inline std::string Overlap(const SkinMesh& s) {
  const MeshTopology& t = s.topology;
  std::map<std::pair<int, int>, std::vector<std::uint32_t>> cells;
  auto corners = [&](std::uint32_t tri) {
    std::array<Eigen::Vector2d, 3> c;
    for (int k = 0; k < 3; ++k) c[static_cast<std::size_t>(k)] = s.model.x0_m.col(t.TriangleVertices(tri)[static_cast<std::size_t>(k)]).head<2>();
    return c;
  };
  const double h = s.def.spacing_m;
  for (std::uint32_t tri = 0; tri < t.Triangles().HighWater(); ++tri) {
    if (!t.Triangles().IsLive(tri) || t.TrianglePart(tri) > kWoundPart) continue;
    const auto c = corners(tri);
    Eigen::Vector2d lo = c[0].cwiseMin(c[1]).cwiseMin(c[2]), hi = c[0].cwiseMax(c[1]).cwiseMax(c[2]);
    for (int x = static_cast<int>(std::floor(lo.x() / h)); x <= static_cast<int>(std::floor(hi.x() / h)); ++x)
      for (int y = static_cast<int>(std::floor(lo.y() / h)); y <= static_cast<int>(std::floor(hi.y() / h)); ++y) {
        for (const std::uint32_t other : cells[{x, y}])
          if (InteriorsOverlap(c, corners(other)))
            return "triangles " + std::to_string(other) + " and " + std::to_string(tri) + " overlap";
        cells[{x, y}].push_back(tri);
      }
  }
  return "";
}

// Every invariant the cutter promises; returns the first violation.
// area_m2 / whole_patch: the rest area and mass must be the whole patch's
// (a cut that stayed inside it); skin nodes only (tool slots are not skin).
inline std::string Violation(const SkinMesh& s, double area_m2, bool whole_patch) {
  const double area_tolerance_m2 = 1e-12 * area_m2;  // rounding of the Bezier points only
  const MeshTopology& t = s.topology;
  std::map<std::pair<std::uint32_t, std::uint32_t>, int> directed;
  double min_area = 1e9;
  for (std::uint32_t tri = 0; tri < t.Triangles().HighWater(); ++tri) {
    if (!t.Triangles().IsLive(tri) || t.TrianglePart(tri) > kWoundPart) continue;  // a tool's triangles
    const auto& v = t.TriangleVertices(tri);
    for (int k = 0; k < 3; ++k) {
      if (!t.Vertices().IsLive(v[static_cast<std::size_t>(k)]) || !s.model.node_live[v[static_cast<std::size_t>(k)]])
        return "triangle " + std::to_string(tri) + " uses a dead node";
      if (++directed[{v[static_cast<std::size_t>(k)], v[static_cast<std::size_t>((k + 1) % 3)]}] > 1)
        return "directed edge used twice (overlap or flipped triangle) at triangle " + std::to_string(tri);
    }
    min_area = std::min(min_area, SignedRestArea(s, tri));
  }
  if (!(min_area > 1e-6 * s.def.spacing_m * s.def.spacing_m)) return "a triangle has rest area " + std::to_string(min_area);
  for (std::int32_t k = 0; k < s.model.NumSprings(); ++k) {
    if (!s.model.node_live[static_cast<std::size_t>(s.model.spring_i[static_cast<std::size_t>(k)])] ||
        !s.model.node_live[static_cast<std::size_t>(s.model.spring_j[static_cast<std::size_t>(k)])])
      return "spring " + std::to_string(k) + " on a dead node";
  }
  for (std::uint32_t v = 0; v < t.Vertices().HighWater(); ++v) {
    const auto tris = t.TrianglesOf(v);
    const bool tool = !tris.empty() && std::all_of(tris.begin(), tris.end(), [&](std::uint32_t x) { return t.TrianglePart(x) > kWoundPart; });
    if (tool) continue;
    if (t.Vertices().IsLive(v) != (s.model.node_live[v] != 0)) return "vertex and node liveness differ at " + std::to_string(v);
    if (t.Vertices().IsLive(v) && t.VertexUses(v) == 0) return "live vertex " + std::to_string(v) + " in no triangle";
  }
  if (const std::string overlap = Overlap(s); !overlap.empty()) return overlap;
  // The wound's bookkeeping: each lip node listed once, live and marked; each
  // wound edge a boundary edge of the skin listed once (else residual stress
  // pulls a face twice).
  std::map<std::uint32_t, int> listed;
  for (const std::uint32_t v : s.lip_nodes) {
    if (++listed[v] > 1) return "lip node " + std::to_string(v) + " listed twice";
    if (!t.Vertices().IsLive(v) || !s.on_lip[v]) return "lip node " + std::to_string(v) + " dead or unmarked";
  }
  std::map<std::pair<std::uint32_t, std::uint32_t>, int> faces;
  for (const auto& [a, b] : s.wound_edges) {
    if (++faces[{a, b}] > 1) return "wound edge " + std::to_string(a) + "-" + std::to_string(b) + " listed twice";
    if (directed[{a, b}] != 1 || directed[{b, a}] != 0) return "wound edge " + std::to_string(a) + "-" + std::to_string(b) + " is not a boundary edge";
  }
  if (whole_patch) {
    const double area = LiveRestArea_m2(s);
    if (std::abs(area - area_m2) > area_tolerance_m2) return "rest area differs by " + std::to_string((area - area_m2) * 1e6) + " mm^2";
    // Mass is conserved or accounted for: every node holds a third of its
    // triangles' rest area times the density, or the floor for a sliver
    // (corners, thin wound triangles); without floors that sums to density x area.
    std::vector<double> share(static_cast<std::size_t>(s.model.num_nodes), 0.0);
    for (std::uint32_t tri = 0; tri < t.Triangles().HighWater(); ++tri) {
      if (!t.Triangles().IsLive(tri) || t.TrianglePart(tri) > kWoundPart) continue;
      for (const auto v : t.TriangleVertices(tri)) share[v] += SignedRestArea(s, tri) / 3.0;
    }
    double want = 0.0, floor_excess = 0.0;
    for (std::size_t v = 0; v < share.size(); ++v) {
      if (!s.model.node_live[v]) continue;
      const double m = s.def.areal_density_kg_per_m2 * share[v];
      want += std::max(m, s.def.min_node_mass_kg);
      floor_excess += std::max(0.0, s.def.min_node_mass_kg - m);
    }
    const double mass = TotalNodeMass_kg(s);
    if (std::abs(mass - want) > 1e-12 * want) return "mass " + std::to_string(mass) + " != " + std::to_string(want);
    if (std::abs(mass - floor_excess - s.def.areal_density_kg_per_m2 * area_m2) > 1e-12 * want)
      return "mass less the floors' excess differs from density x area";
  }
  return "";
}

}  // namespace hapsim::core::test
