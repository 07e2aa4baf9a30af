#include "hapsim/common/log_histogram.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace hapsim::common {

LogHistogram::LogHistogram(double lowest, double highest, double ratio)
    : lowest_(lowest), log_ratio_(std::log(ratio)) {
  if (!(lowest > 0.0) || !(highest > lowest) || !(ratio > 1.0)) {
    throw std::invalid_argument("LogHistogram needs 0 < lowest < highest and ratio > 1");
  }
  upper_edge_.push_back(lowest);
  while (upper_edge_.back() < highest) upper_edge_.push_back(upper_edge_.back() * ratio);
  counts_.assign(upper_edge_.size() + 1, 0);
}

void LogHistogram::Record(double value) {
  if (!std::isfinite(value)) return;  // a statistic of times: nothing sensible to count
  std::size_t bin = 0;
  if (value > lowest_) {
    // Bin b >= 1 holds (lowest * ratio^(b-1), lowest * ratio^b]; the edge
    // table settles rounding in the logarithm.
    bin = static_cast<std::size_t>(std::ceil(std::log(value / lowest_) / log_ratio_));
    bin = std::min(bin, upper_edge_.size());
    while (bin > 1 && value <= upper_edge_[bin - 1]) --bin;
    while (bin < upper_edge_.size() && value > upper_edge_[bin]) ++bin;
  }
  ++counts_[bin];
  min_ = count_ == 0 ? value : std::min(min_, value);
  max_ = count_ == 0 ? value : std::max(max_, value);
  sum_ += value;
  ++count_;
}

void LogHistogram::Clear() {
  std::fill(counts_.begin(), counts_.end(), 0);
  count_ = 0;
  sum_ = min_ = max_ = 0;
}

Percentiles LogHistogram::Summary() const {
  Percentiles p;
  p.count = count_;
  if (count_ == 0) return p;
  p.min = min_;
  p.max = max_;
  p.mean = sum_ / static_cast<double>(count_);
  const auto rank = [&](double q) {
    const std::uint64_t k = NearestRank(q, static_cast<std::size_t>(count_));
    std::uint64_t seen = 0;
    for (std::size_t b = 0; b < counts_.size(); ++b) {
      seen += counts_[b];
      if (seen >= k) return b < upper_edge_.size() ? std::clamp(upper_edge_[b], min_, max_) : max_;
    }
    return max_;
  };
  p.p50 = rank(0.50);
  p.p99 = rank(0.99);
  return p;
}

}  // namespace hapsim::common
