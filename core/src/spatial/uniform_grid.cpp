#include "hapsim/core/spatial/uniform_grid.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace hapsim::core {

UniformGrid::UniformGrid(const Eigen::AlignedBox3d& box, double cell_m, std::size_t max_points) {
  if (box.isEmpty() || !box.min().allFinite() || !box.max().allFinite())
    throw std::invalid_argument("UniformGrid: the box is empty or not finite");
  if (!(cell_m > 0.0 && std::isfinite(cell_m))) throw std::invalid_argument("UniformGrid: cell size must be > 0");
  origin_ = box.min();
  inv_cell_ = 1.0 / cell_m;
  const Eigen::Vector3d extent = box.sizes() * inv_cell_;
  double cells = 1.0;
  for (int k = 0; k < 3; ++k) {
    dims_[k] = std::max(1, static_cast<int>(std::ceil(extent[k])));
    cells *= dims_[k];
  }
  if (cells > static_cast<double>(1 << 24)) throw std::invalid_argument("UniformGrid: more than 2^24 cells");
  cell_start_.assign(static_cast<std::size_t>(cells) + 1, 0);
  items_.assign(max_points, 0);
  point_cell_.assign(max_points, 0);
}

Eigen::Vector3i UniformGrid::CellOf(const Eigen::Vector3d& p) const {
  Eigen::Vector3i c;
  for (int k = 0; k < 3; ++k) {
    const double f = (p[k] - origin_[k]) * inv_cell_;
    // NaN and far-away points land in the border cells (never out of range).
    c[k] = !(f > 0.0) ? 0 : f >= dims_[k] - 1 ? dims_[k] - 1 : static_cast<int>(f);
  }
  return c;
}

void UniformGrid::Build(const Eigen::Matrix3Xd& x_m, std::span<const std::uint8_t> live) {
  const auto n = std::min(static_cast<std::size_t>(x_m.cols()), items_.size());
  std::fill(cell_start_.begin(), cell_start_.end(), 0u);
  for (std::size_t i = 0; i < n; ++i) {
    if (!live.empty() && !live[i]) continue;
    const Eigen::Vector3i c = CellOf(x_m.col(static_cast<Eigen::Index>(i)));
    point_cell_[i] = static_cast<std::uint32_t>(CellIndex(c.x(), c.y(), c.z()));
    ++cell_start_[point_cell_[i] + 1];
  }
  for (std::size_t c = 1; c < cell_start_.size(); ++c) cell_start_[c] += cell_start_[c - 1];
  items_count_ = cell_start_.back();
  // Fill in point order: each cell's items stay sorted by index (deterministic).
  for (std::size_t i = 0; i < n; ++i) {
    if (!live.empty() && !live[i]) continue;
    items_[cell_start_[point_cell_[i]]++] = static_cast<std::uint32_t>(i);
  }
  // cell_start_ now holds each cell's end: shift back by one cell.
  for (std::size_t c = cell_start_.size() - 1; c > 0; --c) cell_start_[c] = cell_start_[c - 1];
  cell_start_[0] = 0;
}

}  // namespace hapsim::core
