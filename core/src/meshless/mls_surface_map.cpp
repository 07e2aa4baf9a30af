#include "hapsim/core/meshless/mls_surface_map.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>

#include <Eigen/Eigenvalues>
#include <Eigen/LU>

#include "hapsim/core/spatial/uniform_grid.h"

namespace hapsim::core {

double CubicSplineWeight(double r) {
  if (r < 0.0) r = -r;
  if (r <= 0.5) return 2.0 / 3.0 - 4.0 * r * r + 4.0 * r * r * r;
  if (r <= 1.0) return 4.0 / 3.0 - 4.0 * r + 4.0 * r * r - 4.0 / 3.0 * r * r * r;
  return 0.0;
}

MlsSurfaceMap BuildMlsSurfaceMap(const Eigen::Matrix3Xd& nodes, const Eigen::Matrix3Xd& surface, double support_m) {
  if (!(support_m > 0.0) || !std::isfinite(support_m)) throw std::invalid_argument("MLS map: support must be > 0");
  if (nodes.cols() == 0) throw std::invalid_argument("MLS map: no nodes");
  if (!nodes.allFinite() || !surface.allFinite()) throw std::invalid_argument("MLS map: positions must be finite");
  Eigen::AlignedBox3d box(nodes.rowwise().minCoeff(), nodes.rowwise().maxCoeff());
  box.extend(box.max() + Eigen::Vector3d::Constant(support_m));
  UniformGrid grid(box, support_m, static_cast<std::size_t>(nodes.cols()));
  grid.Build(nodes);

  MlsSurfaceMap map;
  map.first.push_back(0);
  map.fewest_nodes = std::numeric_limits<std::int32_t>::max();
  std::vector<std::int32_t> around;
  for (Eigen::Index v = 0; v < surface.cols(); ++v) {
    const Eigen::Vector3d X = surface.col(v);
    around.clear();
    grid.ForEachWithin(nodes, X, support_m, [&](std::uint32_t i) {
      if ((nodes.col(i) - X).norm() < support_m) around.push_back(static_cast<std::int32_t>(i));
    });
    std::sort(around.begin(), around.end());
    // Basis in coordinates relative to X and scaled by the support, so A is
    // well scaled whatever the units; then p(X) = (1, 0, 0, 0).
    Eigen::Matrix4d A = Eigen::Matrix4d::Zero();
    for (const std::int32_t i : around) {
      const Eigen::Vector3d r = (nodes.col(i) - X) / support_m;
      const Eigen::Vector4d p(1.0, r.x(), r.y(), r.z());
      A += CubicSplineWeight(r.norm()) * p * p.transpose();
    }
    const Eigen::SelfAdjointEigenSolver<Eigen::Matrix4d> eig(A, Eigen::EigenvaluesOnly);
    const double lo = eig.eigenvalues().minCoeff(), hi = eig.eigenvalues().maxCoeff();
    if (around.size() < 4 || !(lo > 0.0) || hi / lo > 1e8) {
      throw std::invalid_argument("MLS map: surface vertex " + std::to_string(v) + " sees " +
                                  std::to_string(around.size()) +
                                  " nodes within the support, too few or coplanar for a linear fit (raise the support)");
    }
    const Eigen::Vector4d c = A.inverse().col(0);  // A^-1 p(X), A symmetric
    for (const std::int32_t i : around) {
      const Eigen::Vector3d r = (nodes.col(i) - X) / support_m;
      const Eigen::Vector4d p(1.0, r.x(), r.y(), r.z());
      map.node.push_back(i);
      map.phi.push_back(CubicSplineWeight(r.norm()) * c.dot(p));
    }
    map.first.push_back(static_cast<std::int32_t>(map.node.size()));
    map.fewest_nodes = std::min(map.fewest_nodes, static_cast<std::int32_t>(around.size()));
  }
  return map;
}

void MapSurface(const MlsSurfaceMap& map, const Eigen::Matrix3Xd& nodes, Eigen::Matrix3Xd& surface) {
  const auto vertices = static_cast<Eigen::Index>(map.first.size()) - 1;
  for (Eigen::Index v = 0; v < vertices; ++v) {
    Eigen::Vector3d x = Eigen::Vector3d::Zero();
    for (std::int32_t k = map.first[static_cast<std::size_t>(v)]; k < map.first[static_cast<std::size_t>(v) + 1]; ++k) {
      x += map.phi[static_cast<std::size_t>(k)] * nodes.col(map.node[static_cast<std::size_t>(k)]);
    }
    surface.col(v) = x;
  }
}

}  // namespace hapsim::core
