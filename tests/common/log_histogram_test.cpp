// LogHistogram against the exact nearest-rank percentiles of the same
// samples (SampleWindow keeps them all here): never below, and above by at
// most the bin ratio.
#include "hapsim/common/log_histogram.h"

#include <cmath>
#include <random>
#include <stdexcept>

#include <gtest/gtest.h>

namespace hapsim::common {
namespace {

constexpr double kRatio = 1.02;

void ExpectWithinOneBin(double histogram, double exact, const char* what) {
  EXPECT_GE(histogram, exact) << what;
  EXPECT_LE(histogram, exact * kRatio) << what;
}

TEST(LogHistogram, PercentilesAreTheExactOnesRoundedUpToTheirBin) {
  // Round trips of a loaded server: log-normal around 1 ms with a tail.
  std::mt19937_64 rng(7);
  std::lognormal_distribution<double> round_trip_s(std::log(1e-3), 0.8);
  for (int n : {1, 2, 99, 100, 101, 10'000, 200'000}) {
    LogHistogram h(1e-6, 10.0, kRatio);
    SampleWindow exact(static_cast<std::size_t>(n));
    for (int i = 0; i < n; ++i) {
      const double v = round_trip_s(rng);
      h.Record(v);
      exact.Record(v);
    }
    const Percentiles a = h.Summary(), e = exact.Summary();
    ASSERT_EQ(a.count, e.count) << n;
    ExpectWithinOneBin(a.p50, e.p50, "p50");
    ExpectWithinOneBin(a.p99, e.p99, "p99");
    EXPECT_EQ(a.min, e.min) << n;
    EXPECT_EQ(a.max, e.max) << n;
    EXPECT_NEAR(a.mean, e.mean, 1e-12 * e.mean) << n;
  }
}

TEST(LogHistogram, ValuesOnABinEdgeAndOutsideTheRangeAreCountedWhereTheyBelong) {
  LogHistogram h(1e-3, 1.0, 2.0);  // edges 1, 2, 4, ... ms
  for (double v : {2e-3, 2e-3, 2e-3}) h.Record(v);  // exactly on an edge: that bin, not the next
  EXPECT_DOUBLE_EQ(h.Summary().p50, 2e-3);
  h.Clear();
  EXPECT_EQ(h.Summary().count, 0u);
  for (int i = 0; i < 98; ++i) h.Record(1e-9);  // below the range
  h.Record(5.0);                               // above it: the exact max
  h.Record(7.0);
  const Percentiles p = h.Summary();
  EXPECT_EQ(p.count, 100u);
  EXPECT_DOUBLE_EQ(p.p50, 1e-3);  // the underflow bin reports its edge...
  EXPECT_DOUBLE_EQ(p.p99, 7.0);   // ...the overflow bin the max seen
  EXPECT_DOUBLE_EQ(p.max, 7.0);
  EXPECT_DOUBLE_EQ(p.min, 1e-9);
}

TEST(LogHistogram, NonFiniteValuesAreNotCountedAndBadRangesAreRefused) {
  LogHistogram h(1e-6, 1.0, kRatio);
  h.Record(std::nan(""));
  h.Record(HUGE_VAL);
  EXPECT_EQ(h.count(), 0u);
  EXPECT_THROW(LogHistogram(0.0, 1.0, kRatio), std::invalid_argument);
  EXPECT_THROW(LogHistogram(1.0, 0.5, kRatio), std::invalid_argument);
  EXPECT_THROW(LogHistogram(1e-6, 1.0, 1.0), std::invalid_argument);
}

}  // namespace
}  // namespace hapsim::common
