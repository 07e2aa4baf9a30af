#include "hapsim/servo/passivity.h"

#include <algorithm>
#include <cmath>

namespace hapsim::bridge {

PassivityController::Action PassivityController::Control(Eigen::Vector3d& f, const Eigen::Vector3d& v,
                                                         double dt_s) const {
  const double speed_sq = v.squaredNorm();
  if (!(speed_sq > 0.0) || !v.allFinite()) return Action::kNone;  // still (or no velocity): nothing to damp
  const double energy_after_J = energy_J_ - f.dot(v) * dt_s;
  if (!(energy_after_J < 0.0)) return Action::kNone;
  const double needed_Ns_per_m = -energy_after_J / (speed_sq * dt_s);
  if (needed_Ns_per_m <= max_damping_Ns_per_m_) {
    f -= needed_Ns_per_m * v;
    return Action::kCorrected;
  }
  // The device cannot damp the deficit away this tick: the part of the force
  // that pushes along the motion (what gives the hand energy) goes too, so
  // the rendering only dissipates until E is paid back.
  const double along_Ns_per_m = f.dot(v) / speed_sq;
  if (along_Ns_per_m > 0.0) f -= along_Ns_per_m * v;
  f -= max_damping_Ns_per_m_ * v;
  return Action::kBounded;
}

void PassivityController::Observe(const Eigen::Vector3d& commanded, const Eigen::Vector3d& v, double dt_s) {
  const double absorbed_J = -commanded.dot(v) * dt_s;
  if (std::isfinite(absorbed_J)) energy_J_ += absorbed_J;  // a NaN velocity must not poison E for good
}

}  // namespace hapsim::bridge
