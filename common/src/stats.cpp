#include "hapsim/common/stats.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <numeric>

namespace hapsim::common {

std::size_t NearestRank(double q, std::size_t n) {
  return std::clamp<std::size_t>(static_cast<std::size_t>(std::ceil(q * static_cast<double>(n))), 1, n);
}

Percentiles SampleWindow::Summary() const {
  Percentiles p;
  p.count = size_;
  if (size_ == 0) return p;
  std::vector<double> v(ring_.begin(), ring_.begin() + static_cast<std::ptrdiff_t>(size_));
  std::sort(v.begin(), v.end());
  const auto rank = [&](double q) { return v[NearestRank(q, v.size()) - 1]; };
  p.min = v.front();
  p.max = v.back();
  p.p50 = rank(0.50);
  p.p99 = rank(0.99);
  p.mean = std::accumulate(v.begin(), v.end(), 0.0) / static_cast<double>(v.size());
  return p;
}

std::string FormatPercentiles(const Percentiles& p, double scale, const char* unit) {
  char buf[160];
  std::snprintf(buf, sizeof buf, "p50 %.3f / p99 %.3f / max %.3f %s (n=%zu)", p.p50 * scale,
                p.p99 * scale, p.max * scale, unit, p.count);
  return buf;
}

}  // namespace hapsim::common
