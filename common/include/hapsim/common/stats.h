// Latency/jitter statistics over a bounded window of recent samples.
// Record() never allocates after construction (ring buffer), so it may be
// called from the 1 kHz loops; Summary() sorts a copy and is for reports.
#pragma once
#include <cstddef>
#include <string>
#include <vector>

namespace hapsim::common {

struct Percentiles {
  std::size_t count = 0;  // samples in the window
  double min = 0, p50 = 0, p99 = 0, max = 0, mean = 0;
};

// Nearest rank: the k-th smallest of n samples (1-based) is the q-quantile,
// k = ceil(q n) kept within [1, n]. Shared by every percentile we report.
std::size_t NearestRank(double q, std::size_t n);

class SampleWindow {
 public:
  explicit SampleWindow(std::size_t capacity = 1 << 16) : ring_(capacity) {}
  void Record(double value) {
    ring_[next_] = value;
    next_ = (next_ + 1) % ring_.size();
    if (size_ < ring_.size()) ++size_;
    ++total_;
  }
  std::size_t Total() const { return total_; }
  Percentiles Summary() const;

 private:
  std::vector<double> ring_;
  std::size_t next_ = 0, size_ = 0, total_ = 0;
};

// "p50 1.23 / p99 4.56 / max 7.89 <unit> (n=1000)"
std::string FormatPercentiles(const Percentiles& p, double scale, const char* unit);

}  // namespace hapsim::common
