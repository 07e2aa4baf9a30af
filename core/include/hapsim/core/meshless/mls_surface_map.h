// A surface mesh that follows the meshless nodes by moving least squares
// (vascular paper, Zhang et al. 2021, §2.3): each surface vertex X moves with the
// nodes I within d_m of it at rest,
//   x(X) = sum_I phi_I(X) x_I,   phi_I(X) = p(X)^T A(X)^-1 w(|X - x_I| / d_m) p(x_I),
//   A(X) = sum_I w(..) p(x_I) p(x_I)^T,   p = (1, x, y, z)   (linear basis),
// with the cubic-spline weight w(r) = 2/3 - 4r^2 + 4r^3 (r <= 1/2),
// 4/3 - 4r + 4r^2 - 4/3 r^3 (1/2 < r <= 1), 0 beyond. The shape functions
// depend on the rest state only, so Build precomputes them and a tick costs
// one short weighted sum per vertex. Linear completeness gives partition of
// unity (sum phi = 1) and linear reproduction (sum phi x0_I = X): a rigid or
// affine motion of the nodes moves the surface exactly the same way.
#pragma once
#include <cstdint>
#include <vector>

#include <Eigen/Core>

namespace hapsim::core {

double CubicSplineWeight(double r_normalised);

struct MlsSurfaceMap {
  std::vector<std::int32_t> first;  // (vertices + 1): vertex v uses node[first[v] .. first[v+1])
  std::vector<std::int32_t> node;
  std::vector<double> phi;          // shape function value per (vertex, node) pair
  std::int32_t fewest_nodes = 0;
};

// Throws std::invalid_argument if a vertex has fewer than 4 nodes within
// support_m or they are (nearly) coplanar (A(X) condition above 1e8): the
// linear fit is then undetermined. Names the vertex.
MlsSurfaceMap BuildMlsSurfaceMap(const Eigen::Matrix3Xd& nodes_rest_m, const Eigen::Matrix3Xd& surface_rest_m,
                                 double support_m);

// Surface vertex positions (3 x vertices, sized by the caller) from the
// current node positions.
void MapSurface(const MlsSurfaceMap& map, const Eigen::Matrix3Xd& nodes_m, Eigen::Matrix3Xd& surface_m);

}  // namespace hapsim::core
