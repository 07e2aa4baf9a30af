// Minimal Wavefront OBJ parsing for SH fitting: vertices ("v x y z") and
// faces ("f a b c ...", fan-triangulated; "a/b/c" and negative indices
// accepted). Text in, data out: the core does no file I/O.
#pragma once
#include <array>
#include <cstdint>
#include <string_view>
#include <vector>

#include <Eigen/Core>

namespace hapsim::core {

struct ObjMesh {
  Eigen::Matrix3Xd vertices_m;                    // (3 x n), units as in the file
  std::vector<std::array<std::int32_t, 3>> triangles;  // 0-based
};

// Throws std::invalid_argument naming the line for malformed input.
ObjMesh ParseObj(std::string_view text);

// True when every triangle faces away from center (its outward normal, by
// winding, has a positive component along centroid - center): a sufficient
// check that a closed, consistently wound mesh is star-shaped about center.
// Zero-area triangles are skipped.
bool IsStarShapedAbout(const ObjMesh& mesh, const Eigen::Vector3d& center);

}  // namespace hapsim::core
