// Percentiles of a stream too long to keep: counts in geometric bins.
// Record() is O(1) and never allocates (the bins are sized at construction),
// so the 1 kHz loops may call it; Summary() is O(bins). A percentile is
// reported as the upper edge of the bin holding that rank, so it is never
// below the exact nearest-rank value and at most (ratio - 1) of it above;
// min, max, mean and count are exact.
#pragma once
#include <cstdint>
#include <vector>

#include "hapsim/common/stats.h"

namespace hapsim::common {

class LogHistogram {
 public:
  // Values in [lowest, highest] land in bins whose edges grow by `ratio`
  // (> 1); smaller ones count in an underflow bin reported as `lowest`,
  // larger ones in an overflow bin reported as the exact max.
  LogHistogram(double lowest, double highest, double ratio);
  void Record(double value);
  void Clear();
  std::uint64_t count() const { return count_; }
  Percentiles Summary() const;

 private:
  double lowest_, log_ratio_;
  std::vector<double> upper_edge_;     // of each bin; bin 0 is the underflow (edge: lowest)
  std::vector<std::uint64_t> counts_;  // one more than upper_edge_: the overflow bin
  std::uint64_t count_ = 0;
  double sum_ = 0, min_ = 0, max_ = 0;
};

}  // namespace hapsim::common
