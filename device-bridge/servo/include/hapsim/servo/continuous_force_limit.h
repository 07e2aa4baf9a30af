// Continuous-force limit: the motors may give their peak force briefly but
// overheat holding it. An exponential moving average of |F| with time
// constant window_s is held against max_continuous_force_N; while the
// average exceeds it the force is derated by limit / average.
//
// The average is of the force this stage would send on (its input, times
// the watchdog's and the arm button's factor: a zeroed force lets the
// motors cool). Averaging the derated output instead would settle a
// sustained request R at sqrt(R limit), above the limit; averaging the
// input settles it at exactly the limit. Peaks shorter than the window
// pass: from rest, a request R is derated only after
// -window ln(1 - limit/R) seconds. Allocation-free.
#pragma once

#include <Eigen/Core>

namespace hapsim::bridge {

class ContinuousForceLimit {
 public:
  ContinuousForceLimit(double max_continuous_force_N, double window_s)
      : limit_N_(max_continuous_force_N), window_s_(window_s) {}
  // Derates f in place; pass_on: the factor later stages leave of the
  // force (0 while disarmed). Returns true when it derated.
  bool Apply(Eigen::Vector3d& f_W_N, double pass_on, double dt_s);
  double average_N() const { return average_N_; }

 private:
  double limit_N_, window_s_;
  double average_N_ = 0.0;
};

}  // namespace hapsim::bridge
