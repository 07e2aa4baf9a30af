#include "hapsim/servo/model_transition.h"

namespace hapsim::bridge {

Eigen::Vector3d ModelTransition::Base(const Eigen::Vector3d& x, const Eigen::Vector3d& v) const {
  return core::EvaluateLocalForce(from_, x, v) + residual_W_N_;
}

bool ModelTransition::Offer(const core::LocalForceModel& replaced, const Eigen::Vector3d& new_W_N,
                            const Eigen::Vector3d& x, const Eigen::Vector3d& v) {
  if (config_.ticks <= 0) return false;
  const Eigen::Vector3d replaced_W_N = core::EvaluateLocalForce(replaced, x, v);
  if (!replaced_W_N.allFinite() || !new_W_N.allFinite()) {
    active_ = false;
    return false;
  }
  // Within one step of the model it replaces: the same target (a running
  // transition goes on towards the new model), or taken at once.
  const double bound_N = config_.jnd_fraction * replaced_W_N.norm() + config_.jnd_floor_N;
  if ((new_W_N - replaced_W_N).norm() <= bound_N) return false;
  // A jump: blend from the force the stylus feels now.
  const Eigen::Vector3d current_W_N =
      active_ ? Eigen::Vector3d(Base(x, v) + weight_ * (replaced_W_N - Base(x, v))) : replaced_W_N;
  from_ = replaced;
  residual_W_N_ = current_W_N - replaced_W_N;  // B = current at s = 0
  weight_ = 0.0;
  active_ = current_W_N.allFinite();
  return active_;
}

Eigen::Vector3d ModelTransition::Step(const Eigen::Vector3d& model_W_N, const Eigen::Vector3d& x,
                                      const Eigen::Vector3d& v, bool* held_back) {
  *held_back = false;
  Eigen::Vector3d f = model_W_N;
  if (active_) {
    const Eigen::Vector3d base = Base(x, v);
    const Eigen::Vector3d jump = model_W_N - base;
    if (jump.allFinite()) {
      double step = 1.0 / config_.ticks;
      const double bound_N = StepBound();
      if (step * jump.norm() > bound_N) {
        step = bound_N / jump.norm();
        *held_back = true;
      }
      weight_ = weight_ + step;
      if (weight_ > 1.0 - 1e-9) weight_ = 1.0;  // N steps of 1/N sum to 1 - 1 ulp
      f = weight_ >= 1.0 ? model_W_N : Eigen::Vector3d(base + weight_ * jump);
      active_ = weight_ < 1.0;
    } else {
      active_ = false;  // garbage in one model: the chain zeroes it, no blending through it
    }
  }
  last_W_N_ = f.allFinite() ? f : Eigen::Vector3d::Zero();
  return f;
}

}  // namespace hapsim::bridge
