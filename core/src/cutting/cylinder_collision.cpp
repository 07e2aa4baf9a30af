#include "hapsim/core/cutting/cylinder_collision.h"

#include <algorithm>

namespace hapsim::core {

bool InsideCylinder(const Cylinder& c, const Eigen::Vector3d& n) {
  const Eigen::Vector3d axis = c.p1_W_m - c.p0_W_m;
  // Step 1: both base angles at most 90° <=> both dot products >= 0.
  if (axis.dot(n - c.p0_W_m) < 0.0 || (-axis).dot(n - c.p1_W_m) < 0.0) return false;
  // Step 2: distance to the axis line below r (squared, no square root).
  const double len2 = axis.squaredNorm();
  if (len2 == 0.0) return false;
  const double d2 = axis.cross(n - c.p0_W_m).squaredNorm() / len2;
  return d2 < c.radius_m * c.radius_m;
}

Eigen::Vector3d ClosestAxisPoint(const Cylinder& c, const Eigen::Vector3d& n) {
  const Eigen::Vector3d axis = c.p1_W_m - c.p0_W_m;
  const double len2 = axis.squaredNorm();
  const double s = len2 > 0.0 ? std::clamp(axis.dot(n - c.p0_W_m) / len2, 0.0, 1.0) : 0.0;
  return c.p0_W_m + s * axis;
}

Eigen::AlignedBox3d Bounds(const Cylinder& c) {
  const Eigen::Vector3d r = Eigen::Vector3d::Constant(c.radius_m);
  Eigen::AlignedBox3d box(c.p0_W_m.cwiseMin(c.p1_W_m) - r, c.p0_W_m.cwiseMax(c.p1_W_m) + r);
  return box;
}

void CollideBruteForce(const Cylinder& c, const Eigen::Matrix3Xd& x_m, std::span<const std::uint8_t> live,
                       std::vector<std::uint32_t>& out) {
  out.clear();
  for (Eigen::Index i = 0; i < x_m.cols(); ++i) {
    if (!live.empty() && !live[static_cast<std::size_t>(i)]) continue;
    if (InsideCylinder(c, x_m.col(i))) out.push_back(static_cast<std::uint32_t>(i));
  }
}

void CollideWithGrid(const Cylinder& c, const Eigen::Matrix3Xd& x_m, const UniformGrid& grid,
                     std::vector<std::uint32_t>& out) {
  CollideWithShiftedGrid(c, x_m, grid, 0.0, out);
}

double MaxDisplacement_m(const Eigen::Matrix3Xd& x_m, const Eigen::Matrix3Xd& x0_m, std::span<const std::uint8_t> live,
                         Eigen::Index count) {
  double max2 = 0.0;
  for (Eigen::Index i = 0; i < count; ++i) {
    const double d2 = (x_m.col(i) - x0_m.col(i)).squaredNorm();
    const bool is_live = live.empty() || live[static_cast<std::size_t>(i)];
    max2 = is_live && d2 > max2 ? d2 : max2;
  }
  return std::sqrt(max2);
}

void CollideWithShiftedGrid(const Cylinder& c, const Eigen::Matrix3Xd& x_m, const UniformGrid& grid,
                            double max_shift_m, std::vector<std::uint32_t>& out) {
  out.clear();
  Eigen::AlignedBox3d box = Bounds(c);
  box.min().array() -= max_shift_m;
  box.max().array() += max_shift_m;
  grid.ForEachInBox(box, [&](std::uint32_t i) {
    if (InsideCylinder(c, x_m.col(i))) out.push_back(i);
  });
  std::sort(out.begin(), out.end());  // cell order -> index order (deterministic, as brute force)
}

}  // namespace hapsim::core
