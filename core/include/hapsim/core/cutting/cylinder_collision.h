// The cutting paper's cylinder collision (§2.2): a scalpel blade is a
// cylinder with axis p0 -> p1 and radius r. A node N collides when
//   step 1: angle(p0 p1 N) <= 90° and angle(p1 p0 N) <= 90° (N projects onto
//           the segment p0 p1), and
//   step 2: its distance d to the axis is < r.
// The paper tests every node every frame; here a broad phase (a uniform
// grid, spatial/uniform_grid.h — over current positions, or over rest
// positions queried with the largest displacement since) hands the exact
// test only the nodes near the blade. All answer the same set (tested
// against each other).
#pragma once
#include <cstdint>
#include <span>
#include <vector>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "hapsim/core/spatial/uniform_grid.h"

namespace hapsim::core {

struct Cylinder {
  Eigen::Vector3d p0_W_m = Eigen::Vector3d::Zero();  // blade tip end of the axis
  Eigen::Vector3d p1_W_m = Eigen::Vector3d::UnitZ(); // handle end
  double radius_m = 5e-4;
};

// The paper's two-angle + distance test for one node.
bool InsideCylinder(const Cylinder& c, const Eigen::Vector3d& n_W_m);
// The point p on the axis segment closest to n (where the paper's force acts from).
Eigen::Vector3d ClosestAxisPoint(const Cylinder& c, const Eigen::Vector3d& n_W_m);
// The cylinder's bounding box.
Eigen::AlignedBox3d Bounds(const Cylinder& c);

// Nodes inside the cylinder, ascending. `live` (per column of x_m) may be
// empty (all live). `out` is cleared first; with enough reserved capacity
// it never allocates.
void CollideBruteForce(const Cylinder& c, const Eigen::Matrix3Xd& x_m, std::span<const std::uint8_t> live,
                       std::vector<std::uint32_t>& out);
// The same answer through a grid built from the same x_m and live flags.
void CollideWithGrid(const Cylinder& c, const Eigen::Matrix3Xd& x_m, const UniformGrid& grid,
                     std::vector<std::uint32_t>& out);
// The same answer through a grid built from other positions of the same
// points (e.g. their rest positions) from which none has moved more than
// max_shift_m: the query box grows by that much. Lets a scene keep one grid
// between topology changes instead of rebuilding it (O(nodes)) every tick.
// The largest |x_i - x0_i| over the first `count` columns whose live flag is
// set (empty span: every column): the shift CollideWithShiftedGrid needs for
// a grid of x0. One pass.
double MaxDisplacement_m(const Eigen::Matrix3Xd& x_m, const Eigen::Matrix3Xd& x0_m, std::span<const std::uint8_t> live,
                         Eigen::Index count);
void CollideWithShiftedGrid(const Cylinder& c, const Eigen::Matrix3Xd& x_m, const UniformGrid& grid,
                            double max_shift_m, std::vector<std::uint32_t>& out);

}  // namespace hapsim::core
