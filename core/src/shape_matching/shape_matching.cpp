#include "hapsim/core/shape_matching/shape_matching.h"

#include <algorithm>

#include <Eigen/LU>
#include <Eigen/SVD>

namespace hapsim::core {

Eigen::Matrix3d ExtractRotation(const Eigen::Matrix3d& A) {
  const Eigen::JacobiSVD<Eigen::Matrix3d> svd(A, Eigen::ComputeFullU | Eigen::ComputeFullV);
  const Eigen::Matrix3d& U = svd.matrixU();
  const Eigen::Matrix3d& V = svd.matrixV();
  Eigen::Vector3d d(1.0, 1.0, (U * V.transpose()).determinant() < 0.0 ? -1.0 : 1.0);
  return U * d.asDiagonal() * V.transpose();
}

void SpringbackStep(const Eigen::Matrix3Xd& rest_m, const Eigen::VectorXd& mass, double eta_rate_per_step,
                    Eigen::Matrix3Xd& x_m, Eigen::VectorXd& eta) {
  const Eigen::Index n = x_m.cols();
  const double total = mass.sum();
  Eigen::Vector3d p_cm = Eigen::Vector3d::Zero(), p0_cm = Eigen::Vector3d::Zero();
  for (Eigen::Index i = 0; i < n; ++i) {
    p_cm += mass[i] * x_m.col(i);
    p0_cm += mass[i] * rest_m.col(i);
  }
  p_cm /= total;
  p0_cm /= total;
  Eigen::Matrix3d A = Eigen::Matrix3d::Zero();
  for (Eigen::Index i = 0; i < n; ++i)
    A.noalias() += mass[i] * (x_m.col(i) - p_cm) * (rest_m.col(i) - p0_cm).transpose();
  const Eigen::Matrix3d R = ExtractRotation(A);
  for (Eigen::Index i = 0; i < n; ++i) {
    const Eigen::Vector3d goal = R * (rest_m.col(i) - p0_cm) + p_cm;
    x_m.col(i) = goal + eta[i] * (x_m.col(i) - goal);
    eta[i] = std::clamp(eta[i] - eta_rate_per_step, 0.0, 1.0);
  }
}

}  // namespace hapsim::core
