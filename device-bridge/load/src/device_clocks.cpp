#include "hapsim/load/device_clocks.h"

#include <algorithm>
#include <limits>

namespace hapsim::bridge {

DeviceClocks::DeviceClocks(const std::vector<double>& phases_s, const std::vector<double>& rate_ppm, double period_s,
                           double end_s)
    : due_s_(phases_s), period_s_(phases_s.size()), ticks_(phases_s.size(), 0), phase_s_(phases_s), end_s_(end_s) {
  for (std::size_t i = 0; i < period_s_.size(); ++i) {
    period_s_[i] = period_s / (1.0 + (i < rate_ppm.size() ? rate_ppm[i] : 0.0) * 1e-6);
  }
}

double DeviceClocks::NextDueS() const {
  double next = std::numeric_limits<double>::infinity();
  for (const double d : due_s_) next = std::min(next, d);
  return next;
}

void DeviceClocks::TakeDue(double now_s, std::vector<std::size_t>* due, std::vector<double>* due_times_s) {
  due->clear();
  due_times_s->clear();
  for (std::size_t i = 0; i < due_s_.size(); ++i) {
    if (due_s_[i] > now_s || due_s_[i] >= end_s_) continue;
    due->push_back(i);
    due_times_s->push_back(due_s_[i]);
    ++ticks_[i];
    // From the tick count, not by adding periods: no rounding drift over hours.
    due_s_[i] = phase_s_[i] + static_cast<double>(ticks_[i]) * period_s_[i];
    if (now_s - due_s_[i] > 10.0 * period_s_[i]) {  // stalled: re-anchor on now
      phase_s_[i] = now_s - static_cast<double>(ticks_[i]) * period_s_[i];
      due_s_[i] = now_s;
      ++reanchors_;
    }
  }
}

}  // namespace hapsim::bridge
