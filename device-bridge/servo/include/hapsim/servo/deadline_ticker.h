// The servo threads' clock: wakes on absolute deadlines one period apart,
// so sleep overshoot does not accumulate into a slower rate. After a stall
// of more than 10 periods it re-anchors on now instead of bursting through
// the missed ticks. Measures itself: |actual period - nominal| and the
// lateness of each wake behind its deadline. Allocation-free after
// construction.
#pragma once
#include <chrono>
#include <cstdint>

#include "hapsim/common/stats.h"

namespace hapsim::bridge {

class DeadlineTicker {
 public:
  using Clock = std::chrono::steady_clock;
  explicit DeadlineTicker(double rate_hz, std::size_t stats_window = 1 << 17);

  // Sleeps until the next deadline (the first call: now) and returns the
  // wake time since construction [s].
  double Wait();
  double ElapsedS() const;
  std::uint64_t wakes() const { return wakes_; }
  std::uint64_t reanchors() const { return reanchors_; }
  common::Percentiles PeriodError() const { return period_error_s_.Summary(); }
  common::Percentiles Lateness() const { return lateness_s_.Summary(); }

 private:
  double period_s_;
  Clock::duration period_;
  Clock::time_point start_, next_, previous_wake_;
  std::uint64_t wakes_ = 0, reanchors_ = 0;
  common::SampleWindow period_error_s_, lateness_s_;
};

}  // namespace hapsim::bridge
