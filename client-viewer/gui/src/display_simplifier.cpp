#include "hapsim/gui/display_simplifier.h"

#include <cmath>
#include <limits>
#include <unordered_map>

namespace hapsim::gui {

namespace {

struct Cell {
  std::uint32_t vertex = 0;
  double distance2 = std::numeric_limits<double>::infinity();
};

std::uint64_t CellKey(const std::int64_t i[3]) {
  // 21 bits per axis: 2 million cells along each, far more than any mesh
  // the viewer is sent spans at the cell sizes used.
  constexpr std::int64_t kMask = (1 << 21) - 1;
  return (static_cast<std::uint64_t>(i[0] & kMask) << 42) | (static_cast<std::uint64_t>(i[1] & kMask) << 21) |
         static_cast<std::uint64_t>(i[2] & kMask);
}

}  // namespace

namespace {

// Each used vertex's cell key, and per cell the vertex nearest its centre.
struct VertexCells {
  std::vector<std::uint64_t> key_of;  // per vertex
  std::unordered_map<std::uint64_t, Cell> cells;
};

VertexCells AssignCells(const std::vector<float>& positions_m, const std::vector<std::uint32_t>& triangles,
                        double cell_m) {
  const std::size_t vertices = positions_m.size() / 3;
  VertexCells out;
  out.key_of.assign(vertices, 0);
  std::vector<std::uint8_t> used(vertices, 0);
  out.cells.reserve(vertices);
  for (const std::uint32_t v : triangles) {
    if (v >= vertices || used[v]) continue;
    used[v] = 1;
    std::int64_t index[3];
    double offset2 = 0.0;
    for (int k = 0; k < 3; ++k) {
      const double x = static_cast<double>(positions_m[3 * v + static_cast<std::size_t>(k)]) / cell_m;
      index[k] = static_cast<std::int64_t>(std::floor(x));
      const double from_centre = x - (static_cast<double>(index[k]) + 0.5);
      offset2 += from_centre * from_centre;
    }
    out.key_of[v] = CellKey(index);
    Cell& cell = out.cells[out.key_of[v]];
    if (offset2 < cell.distance2) cell = {v, offset2};
  }
  return out;
}

}  // namespace

CoarseTriangles ClusterVertices(const std::vector<float>& positions_m, const std::vector<std::uint32_t>& triangles,
                                const std::vector<std::uint16_t>& parts, double cell_m) {
  CoarseTriangles out;
  out.cell_m = cell_m;
  const std::size_t vertices = positions_m.size() / 3;
  VertexCells cells = AssignCells(positions_m, triangles, cell_m);
  const std::size_t count = std::min(triangles.size() / 3, parts.size());
  out.vertices.reserve(triangles.size());
  out.parts.reserve(count);
  for (std::size_t t = 0; t < count; ++t) {
    std::uint32_t r[3];
    bool valid = true;
    for (int k = 0; k < 3; ++k) {
      const std::uint32_t v = triangles[3 * t + static_cast<std::size_t>(k)];
      if (v >= vertices) {
        valid = false;
        break;
      }
      r[k] = cells.cells[cells.key_of[v]].vertex;
    }
    if (!valid || r[0] == r[1] || r[1] == r[2] || r[0] == r[2]) continue;
    out.vertices.insert(out.vertices.end(), {r[0], r[1], r[2]});
    out.parts.push_back(parts[t]);
  }
  return out;
}

CoarseTriangles SimplifyToBudget(const std::vector<float>& positions_m, const std::vector<std::uint32_t>& triangles,
                                 const std::vector<std::uint16_t>& parts, std::size_t max_triangles) {
  const std::size_t count = std::min(triangles.size() / 3, parts.size());
  if (max_triangles == 0 || count <= max_triangles) {
    CoarseTriangles out;
    out.vertices.assign(triangles.begin(), triangles.begin() + static_cast<std::ptrdiff_t>(3 * count));
    out.parts.assign(parts.begin(), parts.begin() + static_cast<std::ptrdiff_t>(count));
    return out;
  }
  // Start from the mean edge length: a cell that size merges little.
  const std::size_t vertices = positions_m.size() / 3;
  double edges = 0.0;
  std::size_t measured = 0;
  for (std::size_t t = 0; t < count; ++t) {
    const std::uint32_t a = triangles[3 * t], b = triangles[3 * t + 1];
    if (a >= vertices || b >= vertices) continue;
    double d2 = 0.0;
    for (int k = 0; k < 3; ++k) {
      const double d = static_cast<double>(positions_m[3 * a + static_cast<std::size_t>(k)]) -
                       static_cast<double>(positions_m[3 * b + static_cast<std::size_t>(k)]);
      d2 += d * d;
    }
    edges += std::sqrt(d2);
    ++measured;
  }
  double cell_m = measured > 0 && edges > 0.0 ? edges / static_cast<double>(measured) : 1e-3;
  CoarseTriangles out = ClusterVertices(positions_m, triangles, parts, cell_m);
  for (int attempt = 0; attempt < 40 && out.parts.size() > max_triangles; ++attempt) {
    cell_m *= 1.25;
    out = ClusterVertices(positions_m, triangles, parts, cell_m);
  }
  return out;
}

}  // namespace hapsim::gui
