// Rate limit for bad-input warnings: at most one log line per interval, so a
// device or client sending garbage at 1 kHz cannot flood the log.
#pragma once
#include <cstdint>

namespace hapsim::service {

class WarningLimiter {
 public:
  static constexpr std::int64_t kIntervalNs = 2'000'000'000;
  // True (and the interval restarts) if the last warning is older than the interval.
  bool Due(std::int64_t now_ns) {
    if (now_ns - last_ns_ <= kIntervalNs) return false;
    last_ns_ = now_ns;
    return true;
  }

 private:
  std::int64_t last_ns_ = -kIntervalNs - 1;
};

}  // namespace hapsim::service
