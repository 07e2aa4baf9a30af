#include "hapsim/core/shf/sh_fit.h"

#include <Eigen/SVD>
#include <cmath>
#include <limits>
#include <numbers>
#include <sstream>
#include <stdexcept>
#include <string>

#include "hapsim/core/math/eigen_blocking.h"
#include "hapsim/core/math/portable_math.h"

namespace hapsim::core {

namespace {

// FitShSurface's steps, in order.

void CheckShFitSamples(int lmax, Eigen::Index k, const Eigen::Matrix2Xd& theta_phi_rad,
                       const Eigen::Matrix3Xd& points_m) {
  const Eigen::Index n = points_m.cols();
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
}

// Y: one row of basis values per sample (n x k).
Eigen::MatrixXd ShDesignMatrix(const RealShBasis& basis, const Eigen::Matrix2Xd& theta_phi_rad) {
  const Eigen::Index n = theta_phi_rad.cols();
  Eigen::MatrixXd y(n, basis.Size());
  Eigen::VectorXd row(basis.Size());
  for (Eigen::Index i = 0; i < n; ++i) {
    basis.Evaluate(theta_phi_rad(0, i), theta_phi_rad(1, i), row);
    y.row(i) = row.transpose();
  }
  return y;
}

// Y's condition number; samples too sparse to pin the coefficients are
// refused rather than fitted.
double CheckedShFitCondition(const Eigen::BDCSVD<Eigen::MatrixXd>& svd, int lmax, Eigen::Index n,
                             double max_condition_number) {
  const Eigen::VectorXd& s = svd.singularValues();
  const Eigen::Index k = s.size();
  const double cond = s(k - 1) > 0.0 ? s(0) / s(k - 1) : std::numeric_limits<double>::infinity();
  if (!(cond <= max_condition_number)) {
    std::ostringstream msg;
    msg << "FitShSurface: least-squares system is ill-conditioned (condition number " << cond << " > "
        << max_condition_number << ") for Lmax = " << lmax << " with " << n
        << " samples: they do not cover the sphere densely enough; add samples or lower Lmax";
    throw std::invalid_argument(msg.str());
  }
  return cond;
}

// RMS and largest distance from each sample to the fitted surface.
void MeasureShFitResidual(const Eigen::MatrixXd& y, const Eigen::Matrix3Xd& points_m, ShFitResult& out) {
  const Eigen::MatrixX3d residual = y * out.surface.coeffs_m - points_m.transpose();
  const Eigen::VectorXd dist = residual.rowwise().norm();
  out.rms_residual_m = std::sqrt(dist.squaredNorm() / static_cast<double>(points_m.cols()));
  out.max_residual_m = dist.maxCoeff();
}

}  // namespace

ShFitResult FitShSurface(int lmax, const Eigen::Matrix2Xd& theta_phi_rad, const Eigen::Matrix3Xd& points_m,
                         double max_condition_number) {
  PinEigenBlockingSizes();  // the SVD's blocked products: the same bits on every CPU
  const RealShBasis basis(lmax);
  CheckShFitSamples(lmax, basis.Size(), theta_phi_rad, points_m);
  const Eigen::MatrixXd y = ShDesignMatrix(basis, theta_phi_rad);
  const Eigen::BDCSVD<Eigen::MatrixXd> svd(y, Eigen::ComputeThinU | Eigen::ComputeThinV);
  ShFitResult out;
  out.condition_number = CheckedShFitCondition(svd, lmax, points_m.cols(), max_condition_number);
  out.surface.lmax = lmax;
  out.surface.coeffs_m = svd.solve(points_m.transpose());
  MeasureShFitResidual(y, points_m, out);
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
