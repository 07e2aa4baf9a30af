// A uniform grid of cubic cells over points (cell lists): built in O(n) by
// counting sort, queried by box or by radius so a query costs the points
// near it, not the whole set. Shared by the cutting scene's broad phase
// (blade vs skin nodes: a grid of rest positions, rebuilt when a cut changes
// the topology) and
// the meshless vessel's rest neighbourhoods.
//
// Capacity (points and cells) is fixed at construction; Build() never
// allocates. Points outside the grid's box are clamped into its border
// cells, so nothing is ever lost — only queries near the border get slower.
#pragma once
#include <cstdint>
#include <span>
#include <vector>

#include <Eigen/Core>
#include <Eigen/Geometry>

namespace hapsim::core {

class UniformGrid {
 public:
  UniformGrid() = default;
  // box: the region the points mostly lie in [m]; cell_m: the cell edge
  // (>= the radius of typical queries); max_points: the most Build() takes.
  // Throws std::invalid_argument for an empty box, a cell <= 0 or more than
  // 2^24 cells.
  UniformGrid(const Eigen::AlignedBox3d& box, double cell_m, std::size_t max_points);

  // Indexes the points whose `live` flag is set (empty span: all), by their
  // column index in x_m (3 x n, n <= max_points).
  void Build(const Eigen::Matrix3Xd& x_m, std::span<const std::uint8_t> live = {});

  // Calls visit(index) for every indexed point in the cells the box
  // overlaps (a superset of the points inside it; the caller tests them).
  template <class Visit>
  void ForEachInBox(const Eigen::AlignedBox3d& box, Visit&& visit) const {
    if (box.isEmpty()) return;
    const Eigen::Vector3i lo = CellOf(box.min()), hi = CellOf(box.max());
    for (int z = lo.z(); z <= hi.z(); ++z)
      for (int y = lo.y(); y <= hi.y(); ++y)
        for (int x = lo.x(); x <= hi.x(); ++x) {
          const std::size_t c = CellIndex(x, y, z);
          for (std::uint32_t k = cell_start_[c]; k < cell_start_[c + 1]; ++k) visit(items_[k]);
        }
  }
  // Every indexed point within radius_m of p (exact test), in cell order.
  template <class Visit>
  void ForEachWithin(const Eigen::Matrix3Xd& x_m, const Eigen::Vector3d& p, double radius_m, Visit&& visit) const {
    const Eigen::Vector3d r = Eigen::Vector3d::Constant(radius_m);
    const double r2 = radius_m * radius_m;
    ForEachInBox(Eigen::AlignedBox3d(p - r, p + r), [&](std::uint32_t i) {
      if ((x_m.col(i) - p).squaredNorm() <= r2) visit(i);
    });
  }

  Eigen::Vector3i CellOf(const Eigen::Vector3d& p) const;
  std::size_t CellIndex(int x, int y, int z) const {
    return (static_cast<std::size_t>(z) * static_cast<std::size_t>(dims_.y()) + static_cast<std::size_t>(y)) *
               static_cast<std::size_t>(dims_.x()) + static_cast<std::size_t>(x);
  }
  std::size_t Cells() const { return cell_start_.empty() ? 0 : cell_start_.size() - 1; }
  std::size_t Points() const { return items_count_; }

 private:
  Eigen::Vector3d origin_ = Eigen::Vector3d::Zero();
  double inv_cell_ = 1.0;
  Eigen::Vector3i dims_ = Eigen::Vector3i::Ones();
  std::vector<std::uint32_t> cell_start_;  // (cells + 1): cell c holds items_[cell_start_[c], cell_start_[c+1])
  std::vector<std::uint32_t> items_;       // (max_points) point indices, grouped by cell
  std::vector<std::uint32_t> point_cell_;  // (max_points) scratch: cell of each point
  std::size_t items_count_ = 0;
};

}  // namespace hapsim::core
