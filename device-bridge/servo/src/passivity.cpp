#include "hapsim/servo/passivity.h"

#include <algorithm>
#include <cmath>

namespace hapsim::bridge {

PassivityController::Action PassivityController::Control(Eigen::Vector3d& f, const Eigen::Vector3d& v,
                                                         double dt_s) const {
  const double speed_sq = v.squaredNorm();
  if (!(speed_sq > 0.0) || !v.allFinite()) return Action::kNone;  // still (or no velocity): nothing to damp
  // What this tick may give the hand: a share dt/tau of the reserve, so that
  // a reserve running out fades the push over ~tau instead of cutting it in
  // one tick (below zero: the deficit itself).
  const double budget_J = energy_J_ > 0.0 ? energy_J_ * std::min(1.0, dt_s / kReserveFadeS) : energy_J_;
  const double energy_after_J = budget_J - f.dot(v) * dt_s;
  if (!(energy_after_J < 0.0)) return Action::kNone;
  const double needed_Ns_per_m = -energy_after_J / (speed_sq * dt_s);
  // Taking back the force's push along the motion (any share of it, down to
  // none) only removes force, whatever the speed: that needs no cap. Only
  // what would oppose the motion beyond it is damping, which the device can
  // render stably up to its cap.
  const double push_Ns_per_m = std::max(0.0, f.dot(v) / speed_sq);
  if (needed_Ns_per_m <= push_Ns_per_m + max_damping_Ns_per_m_) {
    f -= needed_Ns_per_m * v;
    return Action::kCorrected;
  }
  // The deficit is larger than the push and the device's damping together
  // (E was below zero already): both go, and E rises every such tick until
  // it is paid back.
  f -= (push_Ns_per_m + max_damping_Ns_per_m_) * v;
  return Action::kBounded;
}

void PassivityController::Observe(const Eigen::Vector3d& commanded, const Eigen::Vector3d& v, double dt_s) {
  const double absorbed_J = -commanded.dot(v) * dt_s;
  if (std::isfinite(absorbed_J)) energy_J_ += absorbed_J;  // a NaN velocity must not poison E for good
}

}  // namespace hapsim::bridge
