#include "hapsim/core/shf/sh_fit.h"

#include <Eigen/SVD>
#include <cmath>
#include <numbers>
#include <sstream>
#include <stdexcept>

#include "hapsim/core/math/portable_math.h"

namespace hapsim::core {

ShFitResult FitShSurface(int lmax, const Eigen::Matrix2Xd& theta_phi_rad, const Eigen::Matrix3Xd& points_m,
                         double max_condition_number) {
  const RealShBasis basis(lmax);
  const Eigen::Index n = points_m.cols();
  const Eigen::Index k = basis.Size();
  if (theta_phi_rad.cols() != n) {
    throw std::invalid_argument("FitShSurface: " + std::to_string(theta_phi_rad.cols()) +
                                " parameter pairs for " + std::to_string(n) + " points");
  }
  if (n < k) {
    std::ostringstream msg;
    msg << "FitShSurface: too few samples for Lmax = " << lmax << ": need at least k = (Lmax+1)^2 = " << k
        << ", got " << n << " (add samples or lower Lmax)";
    throw std::invalid_argument(msg.str());
  }
  if (!points_m.allFinite() || !theta_phi_rad.allFinite())
    throw std::invalid_argument("FitShSurface: samples contain NaN or infinity");

  Eigen::MatrixXd y(n, k);
  Eigen::VectorXd row(k);
  for (Eigen::Index i = 0; i < n; ++i) {
    basis.Evaluate(theta_phi_rad(0, i), theta_phi_rad(1, i), row);
    y.row(i) = row.transpose();
  }
  const Eigen::BDCSVD<Eigen::MatrixXd> svd(y, Eigen::ComputeThinU | Eigen::ComputeThinV);
  const Eigen::VectorXd& s = svd.singularValues();
  const double cond = s(k - 1) > 0.0 ? s(0) / s(k - 1) : std::numeric_limits<double>::infinity();
  if (!(cond <= max_condition_number)) {
    std::ostringstream msg;
    msg << "FitShSurface: least-squares system is ill-conditioned (condition number " << cond << " > "
        << max_condition_number << ") for Lmax = " << lmax << " with " << n
        << " samples: they do not cover the sphere densely enough; add samples or lower Lmax";
    throw std::invalid_argument(msg.str());
  }
  ShFitResult out;
  out.surface.lmax = lmax;
  out.surface.coeffs_m = svd.solve(points_m.transpose());
  out.condition_number = cond;
  const Eigen::MatrixX3d residual = y * out.surface.coeffs_m - points_m.transpose();
  const Eigen::VectorXd dist = residual.rowwise().norm();
  out.rms_residual_m = std::sqrt(dist.squaredNorm() / static_cast<double>(n));
  out.max_residual_m = dist.maxCoeff();
  return out;
}

Eigen::Matrix2Xd RadialAngles(const Eigen::Matrix3Xd& points_m, const Eigen::Vector3d& center_m) {
  Eigen::Matrix2Xd out(2, points_m.cols());
  for (Eigen::Index i = 0; i < points_m.cols(); ++i) {
    const Eigen::Vector3d d = points_m.col(i) - center_m;
    if (!(d.norm() > 0.0))
      throw std::invalid_argument("RadialAngles: sample " + std::to_string(i) +
                                  " is at the centre; a star-shaped surface needs the centre inside it");
    DirectionToAngles(d, out(0, i), out(1, i));
  }
  return out;
}

Eigen::Matrix3Xd FibonacciDirections(int n) {
  if (n < 1) throw std::invalid_argument("FibonacciDirections: n must be >= 1");
  Eigen::Matrix3Xd u(3, n);
  const double golden = std::numbers::pi * (3.0 - std::sqrt(5.0));
  for (int i = 0; i < n; ++i) {
    const double z = 1.0 - (2.0 * i + 1.0) / n;
    const double r = std::sqrt(std::max(0.0, 1.0 - z * z));
    u.col(i) << r * pmath::Cos(golden * i), r * pmath::Sin(golden * i), z;
  }
  return u;
}

}  // namespace hapsim::core
