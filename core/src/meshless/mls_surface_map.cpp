#include "hapsim/core/meshless/mls_surface_map.h"

#include <Eigen/Eigenvalues>
#include <Eigen/Geometry>
#include <Eigen/LU>
#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>
#include <vector>

#include "hapsim/core/spatial/uniform_grid.h"

namespace hapsim::core {

double CubicSplineWeight(double r) {
  if (r < 0.0) r = -r;
  if (r <= 0.5) return 2.0 / 3.0 - 4.0 * r * r + 4.0 * r * r * r;
  if (r <= 1.0) return 4.0 / 3.0 - 4.0 * r + 4.0 * r * r - 4.0 / 3.0 * r * r * r;
  return 0.0;
}

namespace {

// BuildMlsSurfaceMap's steps, per surface vertex X, in order.

// The nodes within the support of X, in index order (whatever the grid's).
void FindMlsNodesAround(const UniformGrid& grid, const Eigen::Matrix3Xd& nodes, const Eigen::Vector3d& X,
                        double support_m, std::vector<std::int32_t>& around) {
  around.clear();
  grid.ForEachWithin(nodes, X, support_m, [&](std::uint32_t i) {
    if ((nodes.col(i) - X).norm() < support_m) around.push_back(static_cast<std::int32_t>(i));
  });
  std::sort(around.begin(), around.end());
}

// Basis p = (1, r) in coordinates r relative to X and scaled by the
// support, so A is well scaled whatever the units; then p(X) = (1, 0, 0, 0).
Eigen::Matrix4d MlsMomentMatrix(const Eigen::Matrix3Xd& nodes, const Eigen::Vector3d& X, double support_m,
                                const std::vector<std::int32_t>& around) {
  Eigen::Matrix4d A = Eigen::Matrix4d::Zero();
  for (const std::int32_t i : around) {
    const Eigen::Vector3d r = (nodes.col(i) - X) / support_m;
    const Eigen::Vector4d p(1.0, r.x(), r.y(), r.z());
    A += CubicSplineWeight(r.norm()) * p * p.transpose();
  }
  return A;
}

// A linear fit needs four nodes not in one plane: refused at build.
void CheckMlsMomentMatrix(const Eigen::Matrix4d& A, Eigen::Index v, std::size_t nodes_around) {
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix4d> eig(A, Eigen::EigenvaluesOnly);
  const double lo = eig.eigenvalues().minCoeff(), hi = eig.eigenvalues().maxCoeff();
  if (nodes_around < 4 || !(lo > 0.0) || hi / lo > 1e8) {
    throw std::invalid_argument("MLS map: surface vertex " + std::to_string(v) + " sees " +
                                std::to_string(nodes_around) +
                                " nodes within the support, too few or coplanar for a linear fit (raise the support)");
  }
}

// X's shape functions phi_i = w_i c·p_i with c = A^-1 p(X), appended to the map.
void AppendMlsShapeFunctions(const Eigen::Matrix3Xd& nodes, const Eigen::Vector3d& X, double support_m,
                             const std::vector<std::int32_t>& around, const Eigen::Matrix4d& A, MlsSurfaceMap& map) {
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

}  // namespace

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
    FindMlsNodesAround(grid, nodes, X, support_m, around);
    const Eigen::Matrix4d A = MlsMomentMatrix(nodes, X, support_m, around);
    CheckMlsMomentMatrix(A, v, around.size());
    AppendMlsShapeFunctions(nodes, X, support_m, around, A, map);
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
