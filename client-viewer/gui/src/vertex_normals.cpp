#include "hapsim/gui/vertex_normals.h"

#include <cmath>

namespace hapsim::gui {

void ComputeVertexNormals(const std::vector<float>& positions_m, const std::vector<std::uint32_t>& triangles,
                          std::vector<float>* normals) {
  const std::size_t vertices = positions_m.size() / 3;
  normals->assign(3 * vertices, 0.0f);
  float* n = normals->data();
  const float* p = positions_m.data();
  for (std::size_t t = 0; t + 2 < triangles.size(); t += 3) {
    const std::size_t a = triangles[t], b = triangles[t + 1], c = triangles[t + 2];
    if (a >= vertices || b >= vertices || c >= vertices) continue;
    const float e1[3] = {p[3 * b] - p[3 * a], p[3 * b + 1] - p[3 * a + 1], p[3 * b + 2] - p[3 * a + 2]};
    const float e2[3] = {p[3 * c] - p[3 * a], p[3 * c + 1] - p[3 * a + 1], p[3 * c + 2] - p[3 * a + 2]};
    // |e1 x e2| = twice the area: larger faces weigh more.
    const float face[3] = {e1[1] * e2[2] - e1[2] * e2[1], e1[2] * e2[0] - e1[0] * e2[2],
                           e1[0] * e2[1] - e1[1] * e2[0]};
    for (const std::size_t v : {a, b, c})
      for (int k = 0; k < 3; ++k) n[3 * v + k] += face[k];
  }
  for (std::size_t v = 0; v < vertices; ++v) {
    const float length = std::sqrt(n[3 * v] * n[3 * v] + n[3 * v + 1] * n[3 * v + 1] + n[3 * v + 2] * n[3 * v + 2]);
    if (length > 1e-30f)
      for (int k = 0; k < 3; ++k) n[3 * v + k] /= length;
  }
}

}  // namespace hapsim::gui
