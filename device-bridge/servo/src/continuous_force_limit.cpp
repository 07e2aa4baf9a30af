#include "hapsim/servo/continuous_force_limit.h"

#include <cmath>

namespace hapsim::bridge {

bool ContinuousForceLimit::Apply(Eigen::Vector3d& f, double pass_on, double dt_s) {
  // Exact for a sample held over dt: the average after n ticks of a
  // constant R from rest is R (1 - exp(-n dt / window)).
  const double weight = 1.0 - std::exp(-dt_s / window_s_);
  average_N_ += weight * (f.norm() * pass_on - average_N_);
  if (!(average_N_ > limit_N_) || f.isZero(0.0)) return false;
  f *= limit_N_ / average_N_;
  return true;
}

}  // namespace hapsim::bridge
