// Meshless point-primitive elasticity after Müller et al. 2004, "Point based
// animation of elastic, plastic and melting objects" (vascular paper, Zhang
// et al. 2021, §2.1): Def -> BuildMeshlessModel -> MeshlessModel (immutable,
// everything that depends on the rest state only), forces in
// meshless_forces.h.
//
// Each node i has mass m_i and volume v_i and sees the neighbours j within
// the support radius h at rest (rest neighbourhoods: the material does not
// change neighbours as it deforms). With x_ij = x_j - x_i at rest and the
// kernel w_ij = w(|x_ij|, h), the moment matrix is
//   A_i = sum_j m_j x_ij x_ij^T w_ij
// and the displacement gradient at i is the MLS fit
//   H_i = du/dX (i) = sum_j (u_j - u_i) d_ij^T,   d_ij = A_i^-1 m_j x_ij w_ij,
// which Build precomputes as one 3-vector d_ij per neighbour pair, so a
// tick's gradient is a short sum and no matrix is inverted after Build.
// A neighbourhood whose A_i is singular or ill-conditioned (fewer than four
// non-coplanar neighbours, e.g. a node on a thin shell seeing one layer)
// cannot give a gradient: Build refuses it and names the node.
#pragma once
#include <cstdint>
#include <string>
#include <vector>

#include <Eigen/Core>

namespace hapsim::core {

struct MeshlessDef {
  Eigen::Matrix3Xd x0_m;                // rest positions (3 x n)
  std::vector<double> mass_kg;          // (n)
  std::vector<double> volume_m3;        // (n): each node's share of the body's volume
  std::vector<std::uint8_t> fixed;      // (n) 1: position held (anchored); empty: none
  double support_radius_m = 0.0;        // h: neighbours within h at rest
  double youngs_modulus_Pa = 0.0;       // E
  double poisson_ratio = 0.0;           // nu, in [0, 0.5)
  double damping_per_s = 0.0;           // mass-proportional damping c/m [1/s] (f = -c_m m v)
  // A_i with condition number (largest/smallest eigenvalue) above this is
  // refused: the gradient would amplify round-off by as much.
  double max_moment_condition = 1e6;
};

struct MeshlessModel {
  std::int32_t n = 0;
  Eigen::Matrix3Xd x0_m;
  Eigen::VectorXd mass_kg, inv_mass_per_kg, volume_m3;
  std::vector<std::uint8_t> fixed;
  double support_radius_m = 0.0;
  double lambda_Pa = 0.0, mu_Pa = 0.0;  // Lamé parameters from E, nu
  double damping_per_s = 0.0;
  // Rest neighbourhoods in CSR form: node i's neighbours are
  // neighbour[first[i] .. first[i+1]), with d_ij in gradient_weight's columns.
  std::vector<std::int32_t> first;      // (n + 1)
  std::vector<std::int32_t> neighbour;  // (pairs)
  Eigen::Matrix3Xd gradient_weight;     // (3 x pairs): d_ij = A_i^-1 m_j x_ij w_ij
  Eigen::Matrix3Xd gradient_self;       // (3 x n): -sum_j d_ij (the u_i coefficient)
  double worst_moment_condition = 0.0;  // largest cond(A_i) accepted
  std::int32_t fewest_neighbours = 0;
};

// Müller et al.'s kernel (poly6): w(r, h) = 315 / (64 pi h^9) (h^2 - r^2)^3
// for r < h, else 0 [1/m^3]. Its scale cancels in d_ij (A_i^-1 has the
// inverse scale), so only its shape matters.
double MeshlessKernel(double r_m, double h_m);

// Throws std::invalid_argument naming the problem: sizes, non-positive
// masses or volumes, E <= 0, nu outside [0, 0.5), h <= 0, a node with an
// ill-conditioned or singular moment matrix (its index, neighbour count and
// condition number).
MeshlessModel BuildMeshlessModel(const MeshlessDef& def);

// Lamé parameters of an isotropic linear material.
double LameLambda(double youngs_modulus_Pa, double poisson_ratio);
double LameMu(double youngs_modulus_Pa, double poisson_ratio);

}  // namespace hapsim::core
