#include "hapsim/core/shf/limb_segment.h"

#include <cmath>

#include "hapsim/core/math/portable_math.h"
#include "hapsim/core/shf/sh_fit.h"

namespace hapsim::core {

double LimbSegmentRadius_m(const LimbSegmentDef& d, const Eigen::Vector3d& u_B) {
  const Eigen::Vector3d u = u_B.normalized();
  const double p = d.squareness;
  // Superquadric |z/a|^p + ((x/b)² + (y/c)²)^(p/2) = 1 along the ray s·u.
  const double axial = pmath::Pow(std::abs(u.z()) / d.half_length_m, p);
  const double cross = pmath::Pow(pmath::Pow(u.x() / d.radius_x_m, 2) + pmath::Pow(u.y() / d.radius_y_m, 2), p / 2);
  const double r_sq = pmath::Pow(axial + cross, -1.0 / p);
  const double s = (u.z() - d.belly_center_uz) / d.belly_width_uz;
  return r_sq * (1.0 + d.belly_amplitude * pmath::Exp(-s * s));
}

Eigen::Matrix3Xd SampleLimbSegment_m(const LimbSegmentDef& def, int n, double inset_m) {
  Eigen::Matrix3Xd u = FibonacciDirections(n);
  for (int i = 0; i < n; ++i) u.col(i) *= LimbSegmentRadius_m(def, u.col(i)) - inset_m;
  return u;
}

}  // namespace hapsim::core
