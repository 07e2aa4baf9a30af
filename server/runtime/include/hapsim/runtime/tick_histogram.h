// A histogram of durations the 1 kHz tick feeds without a lock: fixed
// bucket bounds, relaxed atomic counts and an integer-nanosecond sum, so an
// observation is a short scan and two atomic adds and a scrape never blocks
// a tick (prometheus-cpp's Histogram::Observe takes a mutex that its Collect
// holds while copying). The metrics endpoint reads it into prometheus-cpp's
// histogram model at scrape time.
#pragma once
#include <array>
#include <atomic>
#include <cstddef>
#include <cstdint>

namespace hapsim::service {

class TickHistogram {
 public:
  // Upper bounds [s] of the finite buckets: 10 us to 50 ms in 1-2-5 steps
  // (a tick's work, its start delay, a pose's wait for its model); +Inf is
  // the last bucket.
  static constexpr std::array<double, 12> kUpperBounds_s = {1e-5, 2e-5, 5e-5, 1e-4, 2e-4, 5e-4,
                                                            1e-3, 2e-3, 5e-3, 1e-2, 2e-2, 5e-2};
  static constexpr std::size_t kBuckets = kUpperBounds_s.size() + 1;

  // Thread-safe, lock-free, never allocates. Negative durations count as 0.
  void Observe_ns(std::int64_t duration_ns) {
    const std::int64_t ns = duration_ns > 0 ? duration_ns : 0;
    const double s = static_cast<double>(ns) * 1e-9;
    std::size_t b = 0;
    while (b < kUpperBounds_s.size() && s > kUpperBounds_s[b]) ++b;
    counts_[b].fetch_add(1, std::memory_order_relaxed);
    sum_ns_.fetch_add(static_cast<std::uint64_t>(ns), std::memory_order_relaxed);
  }

  struct Snapshot {
    std::array<std::uint64_t, kBuckets> counts{};  // per bucket, not cumulative; the last is +Inf
    double sum_s = 0.0;
  };
  // Not atomic across buckets: a scrape during a tick may see a count
  // without its sum (Prometheus tolerates it; the next scrape is whole).
  Snapshot Read() const {
    Snapshot s;
    for (std::size_t b = 0; b < kBuckets; ++b) s.counts[b] = counts_[b].load(std::memory_order_relaxed);
    s.sum_s = static_cast<double>(sum_ns_.load(std::memory_order_relaxed)) * 1e-9;
    return s;
  }

 private:
  std::array<std::atomic<std::uint64_t>, kBuckets> counts_{};
  std::atomic<std::uint64_t> sum_ns_{0};
};

}  // namespace hapsim::service
