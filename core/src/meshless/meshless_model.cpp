#include "hapsim/core/meshless/meshless_model.h"

#include <Eigen/Eigenvalues>
#include <Eigen/Geometry>
#include <Eigen/LU>
#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <stdexcept>
#include <string>
#include <vector>

#include "hapsim/core/spatial/uniform_grid.h"

namespace hapsim::core {

namespace {

void CheckMeshlessDef(const MeshlessDef& d) {
  const auto n = static_cast<std::size_t>(d.x0_m.cols());
  if (n == 0) throw std::invalid_argument("meshless: no nodes");
  if (d.mass_kg.size() != n || d.volume_m3.size() != n || (!d.fixed.empty() && d.fixed.size() != n)) {
    throw std::invalid_argument("meshless: mass, volume and fixed need one entry per node");
  }
  if (!d.x0_m.allFinite()) throw std::invalid_argument("meshless: rest positions must be finite");
  for (std::size_t i = 0; i < n; ++i) {
    if (!(d.mass_kg[i] > 0.0) || !(d.volume_m3[i] > 0.0) || !std::isfinite(d.mass_kg[i]) ||
        !std::isfinite(d.volume_m3[i])) {
      throw std::invalid_argument("meshless: node " + std::to_string(i) + " needs a positive mass and volume");
    }
  }
  if (!(d.support_radius_m > 0.0) || !std::isfinite(d.support_radius_m)) {
    throw std::invalid_argument("meshless: support radius must be > 0");
  }
  if (!(d.youngs_modulus_Pa > 0.0) || !std::isfinite(d.youngs_modulus_Pa)) {
    throw std::invalid_argument("meshless: Young's modulus must be > 0");
  }
  if (!(d.poisson_ratio >= 0.0 && d.poisson_ratio < 0.5)) {
    throw std::invalid_argument("meshless: Poisson's ratio must be in [0, 0.5)");
  }
  if (!(d.damping_per_s >= 0.0) || !std::isfinite(d.damping_per_s)) {
    throw std::invalid_argument("meshless: damping must be >= 0");
  }
  if (!(d.max_moment_condition > 1.0)) throw std::invalid_argument("meshless: max moment condition must be > 1");
}

}  // namespace

double MeshlessKernel(double r_m, double h_m) {
  if (r_m >= h_m) return 0.0;
  const double q = h_m * h_m - r_m * r_m;
  const double h3 = h_m * h_m * h_m;  // h^9 as products: libm's pow differs per CPU
  return 315.0 / (64.0 * std::numbers::pi * (h3 * h3 * h3)) * q * q * q;
}

double LameLambda(double E, double nu) { return E * nu / ((1.0 + nu) * (1.0 - 2.0 * nu)); }
double LameMu(double E, double nu) { return E / (2.0 * (1.0 + nu)); }

namespace {

// BuildMeshlessModel's steps, in order.

// Node arrays and the material.
void CopyMeshlessNodes(const MeshlessDef& def, MeshlessModel& m) {
  m.n = static_cast<std::int32_t>(def.x0_m.cols());
  m.x0_m = def.x0_m;
  m.mass_kg = Eigen::Map<const Eigen::VectorXd>(def.mass_kg.data(), m.n);
  m.inv_mass_per_kg = m.mass_kg.cwiseInverse();
  m.volume_m3 = Eigen::Map<const Eigen::VectorXd>(def.volume_m3.data(), m.n);
  m.fixed = def.fixed.empty() ? std::vector<std::uint8_t>(static_cast<std::size_t>(m.n), 0) : def.fixed;
  m.support_radius_m = def.support_radius_m;
  m.lambda_Pa = LameLambda(def.youngs_modulus_Pa, def.poisson_ratio);
  m.mu_Pa = LameMu(def.youngs_modulus_Pa, def.poisson_ratio);
  m.damping_per_s = def.damping_per_s;
}

// Rest neighbourhoods (m.first, m.neighbour) from a grid with cells one
// support radius wide.
void FindMeshlessRestNeighbourhoods(const MeshlessDef& def, MeshlessModel& m) {
  const double h = def.support_radius_m;
  Eigen::AlignedBox3d box(def.x0_m.rowwise().minCoeff(), def.x0_m.rowwise().maxCoeff());
  box.extend(box.max() + Eigen::Vector3d::Constant(h));
  UniformGrid grid(box, h, static_cast<std::size_t>(m.n));
  grid.Build(def.x0_m);
  m.first.assign(static_cast<std::size_t>(m.n) + 1, 0);
  std::vector<std::int32_t> around;
  for (std::int32_t i = 0; i < m.n; ++i) {
    around.clear();
    grid.ForEachWithin(def.x0_m, def.x0_m.col(i), h, [&](std::uint32_t j) {
      if (static_cast<std::int32_t>(j) != i && (def.x0_m.col(j) - def.x0_m.col(i)).norm() < h) {
        around.push_back(static_cast<std::int32_t>(j));
      }
    });
    std::sort(around.begin(), around.end());  // deterministic order whatever the grid's
    m.neighbour.insert(m.neighbour.end(), around.begin(), around.end());
    m.first[static_cast<std::size_t>(i) + 1] = static_cast<std::int32_t>(m.neighbour.size());
  }
}

// Node i's moment matrix A_i = sum_j m_j w_ij x_ij x_ij^T over its rest
// neighbourhood (entries b to e of m.neighbour).
Eigen::Matrix3d MeshlessMomentMatrix(const MeshlessDef& def, const MeshlessModel& m, std::int32_t i, std::size_t b,
                                     std::size_t e) {
  Eigen::Matrix3d A = Eigen::Matrix3d::Zero();
  for (std::size_t k = b; k < e; ++k) {
    const std::int32_t j = m.neighbour[k];
    const Eigen::Vector3d xij = def.x0_m.col(j) - def.x0_m.col(i);
    A += m.mass_kg[j] * MeshlessKernel(xij.norm(), def.support_radius_m) * xij * xij.transpose();
  }
  return A;
}

// A_i's condition number; a thin neighbourhood (too few or coplanar
// neighbours) cannot give a gradient, so it is refused here, at build.
double CheckedMeshlessMomentCondition(const MeshlessDef& def, const Eigen::Matrix3d& A, std::int32_t i,
                                      std::size_t neighbours) {
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eig(A, Eigen::EigenvaluesOnly);
  const double lo = eig.eigenvalues().minCoeff(), hi = eig.eigenvalues().maxCoeff();
  const double condition = lo > 0.0 ? hi / lo : std::numeric_limits<double>::infinity();
  if (!(condition <= def.max_moment_condition)) {
    throw std::invalid_argument("meshless: node " + std::to_string(i) + " has " + std::to_string(neighbours) +
                                " neighbours within the support radius and a moment matrix with condition " +
                                std::to_string(condition) +
                                " (needs >= 4 non-coplanar neighbours: raise the support radius)");
  }
  return condition;
}

// Node i's per-pair gradient weights d_ij = A_i^-1 m_j w_ij x_ij, and their
// negated sum (the weight of x_i itself).
void StoreMeshlessGradientWeights(const MeshlessDef& def, const Eigen::Matrix3d& A, std::int32_t i, std::size_t b,
                                  std::size_t e, MeshlessModel& m) {
  const Eigen::Matrix3d A_inv = A.inverse();
  Eigen::Vector3d self = Eigen::Vector3d::Zero();
  for (std::size_t k = b; k < e; ++k) {
    const std::int32_t j = m.neighbour[k];
    const Eigen::Vector3d xij = def.x0_m.col(j) - def.x0_m.col(i);
    const Eigen::Vector3d d = A_inv * (m.mass_kg[j] * MeshlessKernel(xij.norm(), def.support_radius_m) * xij);
    m.gradient_weight.col(static_cast<Eigen::Index>(k)) = d;
    self -= d;
  }
  m.gradient_self.col(i) = self;
}

// Moment matrices and the per-pair gradient weights d_ij.
void ComputeMeshlessGradientWeights(const MeshlessDef& def, MeshlessModel& m) {
  m.gradient_weight.resize(3, static_cast<Eigen::Index>(m.neighbour.size()));
  m.gradient_self.resize(3, m.n);
  m.fewest_neighbours = std::numeric_limits<std::int32_t>::max();
  for (std::int32_t i = 0; i < m.n; ++i) {
    const auto b = static_cast<std::size_t>(m.first[static_cast<std::size_t>(i)]);
    const auto e = static_cast<std::size_t>(m.first[static_cast<std::size_t>(i) + 1]);
    m.fewest_neighbours = std::min(m.fewest_neighbours, static_cast<std::int32_t>(e - b));
    const Eigen::Matrix3d A = MeshlessMomentMatrix(def, m, i, b, e);
    const double condition = CheckedMeshlessMomentCondition(def, A, i, e - b);
    m.worst_moment_condition = std::max(m.worst_moment_condition, condition);
    StoreMeshlessGradientWeights(def, A, i, b, e, m);
  }
}

}  // namespace

MeshlessModel BuildMeshlessModel(const MeshlessDef& def) {
  CheckMeshlessDef(def);
  MeshlessModel m;
  CopyMeshlessNodes(def, m);
  FindMeshlessRestNeighbourhoods(def, m);
  ComputeMeshlessGradientWeights(def, m);
  return m;
}

}  // namespace hapsim::core
