// The devices' own servo clocks, as a classroom has them: every trainee's
// device ticks on its own crystal, so the poses reach the server spread over
// the period and drifting against each other, not in lockstep. Device i's
// tick k is due at
//     t_i(k) = phase_i + k * period_i,   period_i = period / (1 + ppm_i * 1e-6)
// (a clock fast by ppm_i ticks that much more often). hapsim-load's servo
// thread sleeps until the earliest due tick and steps every device due by
// then. A device more than 10 periods behind (the thread stalled) is
// re-anchored on now instead of bursting through the missed ticks, as
// DeadlineTicker does. A run that ends at end_s has no tick due at or after
// it, however late the thread wakes for its last ones. Allocation-free after
// construction.
#pragma once
#include <cstddef>
#include <cstdint>
#include <limits>
#include <vector>

namespace hapsim::bridge {

class DeviceClocks {
 public:
  // phases_s[i] in [0, period_s), rate_ppm[i] each device's rate error;
  // end_s [s since the start] the run's end (none by default).
  DeviceClocks(const std::vector<double>& phases_s, const std::vector<double>& rate_ppm, double period_s,
               double end_s = std::numeric_limits<double>::infinity());

  std::size_t devices() const { return due_s_.size(); }
  // The earliest due tick of any device [s since the start].
  double NextDueS() const;
  // Every device due at or before now_s (and before the end), in index
  // order, into *due (capacity reserved for all devices) with each one's due
  // time; advances each to its next tick.
  void TakeDue(double now_s, std::vector<std::size_t>* due, std::vector<double>* due_times_s);
  std::uint64_t reanchors() const { return reanchors_; }
  double period_s(std::size_t i) const { return period_s_[i]; }

 private:
  std::vector<double> due_s_, period_s_;
  std::vector<std::uint64_t> ticks_;  // ticks taken, per device
  std::vector<double> phase_s_;
  double end_s_;
  std::uint64_t reanchors_ = 0;
};

}  // namespace hapsim::bridge
