// A coarser triangle list for drawing a mesh finer than the screen can show.
// Software rendering (Mesa llvmpipe) pays per triangle, whether it covers
// 3 pixels or 300: a 50k-vertex sheet (99k triangles) in a 900x720 view is
// ~3 pixels a triangle and cannot be drawn at 60 fps on two cores. Above a
// triangle budget the viewer draws this instead: vertices are merged per
// cubic cell onto one of them (vertex clustering), so the coarse triangles
// still index the full position array — the mesh moves every frame without
// recomputing anything, and per-vertex normals still come from the full
// mesh. Recomputed only when the topology or the budget changes.
#pragma once
#include <cstddef>
#include <cstdint>
#include <vector>

namespace hapsim::gui {

struct CoarseTriangles {
  std::vector<std::uint32_t> vertices;  // 3 per kept triangle: slots of the full position array
  std::vector<std::uint16_t> parts;     // 1 per kept triangle
  double cell_m = 0.0;                  // 0: not simplified (the input as is)
};

// Merges the vertices of each cell of `cell_m` (cells of the grid through the
// origin) onto the one nearest the cell's centre; drops triangles left with a
// repeated vertex. Triangles keep their winding and part.
CoarseTriangles ClusterVertices(const std::vector<float>& positions_m, const std::vector<std::uint32_t>& triangles,
                                const std::vector<std::uint16_t>& parts, double cell_m);

// The input itself when it has at most max_triangles (or max_triangles is 0),
// else ClusterVertices with the smallest cell (growing by 1.25x from the
// mean triangle size) whose result fits.
CoarseTriangles SimplifyToBudget(const std::vector<float>& positions_m, const std::vector<std::uint32_t>& triangles,
                                 const std::vector<std::uint16_t>& parts, std::size_t max_triangles);

}  // namespace hapsim::gui
