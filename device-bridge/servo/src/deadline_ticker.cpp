#include "hapsim/servo/deadline_ticker.h"

#include <cmath>
#include <thread>

namespace hapsim::bridge {

DeadlineTicker::DeadlineTicker(double rate_hz, std::size_t stats_window)
    : period_s_(1.0 / rate_hz),
      period_(std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(period_s_))),
      start_(Clock::now()),
      next_(start_),
      previous_wake_(start_),
      period_error_s_(stats_window),
      lateness_s_(stats_window) {}

double DeadlineTicker::Wait() {
  if (wakes_ > 0) {
    next_ += period_;
    if (Clock::now() - next_ > 10 * period_) {  // stalled: re-anchor
      next_ = Clock::now();
      ++reanchors_;
    }
  }
  std::this_thread::sleep_until(next_);
  const auto wake = Clock::now();
  if (wakes_ > 0) {
    period_error_s_.Record(std::abs(std::chrono::duration<double>(wake - previous_wake_).count() - period_s_));
  }
  lateness_s_.Record(std::chrono::duration<double>(wake - next_).count());
  previous_wake_ = wake;
  ++wakes_;
  return std::chrono::duration<double>(wake - start_).count();
}

double DeadlineTicker::ElapsedS() const { return std::chrono::duration<double>(Clock::now() - start_).count(); }

}  // namespace hapsim::bridge
