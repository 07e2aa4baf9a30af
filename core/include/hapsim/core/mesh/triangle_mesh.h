// A triangle mesh as plain arrays: what the core takes from a mesh file
// (hapsim::io reads the files; the core does no file I/O).
#pragma once
#include <array>
#include <cstdint>
#include <vector>

#include <Eigen/Core>

namespace hapsim::core {

struct TriangleMesh {
  Eigen::Matrix3Xd vertices_m;                          // (3 x n) [m], or the source's units
  std::vector<std::array<std::int32_t, 3>> triangles;  // 0-based vertex indices, counter-clockwise seen from outside
};

// True when every triangle faces away from center (its outward normal, by
// winding, has a positive component along centroid - center): a sufficient
// check that a closed, consistently wound mesh is star-shaped about center.
// Zero-area triangles are skipped; an empty mesh is not star-shaped.
bool IsStarShapedAbout(const TriangleMesh& mesh, const Eigen::Vector3d& center);

}  // namespace hapsim::core
