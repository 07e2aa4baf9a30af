#include "hapsim/core/mesh/triangle_mesh.h"

#include <Eigen/Geometry>

namespace hapsim::core {

bool IsStarShapedAbout(const TriangleMesh& mesh, const Eigen::Vector3d& center) {
  for (const auto& t : mesh.triangles) {
    const Eigen::Vector3d a = mesh.vertices_m.col(t[0]), b = mesh.vertices_m.col(t[1]),
                          c = mesh.vertices_m.col(t[2]);
    const Eigen::Vector3d n = (b - a).cross(c - a);
    if (n.squaredNorm() == 0.0) continue;  // degenerate (e.g. collapsed pole row): no orientation
    if (!(n.dot((a + b + c) / 3.0 - center) > 0.0)) return false;
  }
  return !mesh.triangles.empty();
}

}  // namespace hapsim::core
