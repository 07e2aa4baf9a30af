// The continuous-force limit: an exponential moving average of |F| (time
// constant 1 s) held against 0.88 N, the PHANTOM Omni's nominal continuous
// force. Checked against the closed form: from rest, a constant request R
// averages R (1 - exp(-t / 1 s)), and the output is R while that is at most
// the limit, R limit / average after.
#include "hapsim/servo/continuous_force_limit.h"

#include <gtest/gtest.h>

#include <cmath>

#include "hapsim/servo/force_safety.h"
#include "safety_test_setup.h"

// Its own namespace: the test files are compiled in batches (unity build).
namespace hapsim::bridge::continuous_force_limit_test {
namespace {

constexpr double kDt = 0.001;
constexpr double kLimitN = 0.88;

ForceSafety ContinuousLimitOnly(const DeviceLimits& device = {}) {
  SafetyConfig c = test::QuietChain();
  c.max_continuous_force_N = kLimitN;
  c.continuous_window_s = 1.0;
  return ForceSafety(c, device);
}

double ClosedFormOutput(double request_N, double limit_N, int ticks) {
  const double average_N = request_N * (1.0 - std::exp(-ticks * kDt / 1.0));
  return average_N > limit_N ? request_N * limit_N / average_N : request_N;
}

// 2 N held for 10 s: the output follows the closed form within 1e-9 N
// every tick, is first derated on tick 580 (-1000 ln(1 - 0.88/2) = 579.8)
// and ends within 1e-4 N of the limit (closed form: 0.88 / (1 - e^-10) =
// 0.880040 N).
TEST(ContinuousForceLimit, ASustainedRequestAboveTheLimitSettlesAtTheLimit) {
  ForceSafety s = ContinuousLimitOnly();
  const double request_N = 2.0;
  double f_N = 0.0;
  for (int n = 1; n <= 10000; ++n) {
    f_N = s.Apply({0, 0, request_N}, 0.001, kDt).z();
    ASSERT_NEAR(f_N, ClosedFormOutput(request_N, kLimitN, n), 1e-9) << "tick " << n;
    if (n == 579) {
      EXPECT_EQ(s.counters().derated, 0u);
    }
  }
  EXPECT_NEAR(f_N, kLimitN, 1e-4);
  EXPECT_EQ(s.counters().derated, 10000u - 579u);
}

// A 2 N peak of 0.5 s (under the 0.58 s it takes to reach the limit's
// average) passes exactly; after 1 s of rest the average has decayed by
// e^-1 and a second peak of 0.2 s passes too.
TEST(ContinuousForceLimit, PeaksShorterThanTheWindowPassUndiminished) {
  ForceSafety s = ContinuousLimitOnly();
  for (int n = 0; n < 500; ++n) ASSERT_EQ(s.Apply({0, 0, 2.0}, 0.001, kDt).z(), 2.0) << "tick " << n;
  const double after_peak_N = 2.0 * (1.0 - std::exp(-0.5));
  EXPECT_NEAR(s.average_force_N(), after_peak_N, 1e-9);
  for (int n = 0; n < 1000; ++n) s.Apply(Eigen::Vector3d::Zero(), 0.001, kDt);
  EXPECT_NEAR(s.average_force_N(), after_peak_N * std::exp(-1.0), 1e-9);
  for (int n = 0; n < 200; ++n) ASSERT_EQ(s.Apply({0, 0, 2.0}, 0.001, kDt).z(), 2.0) << "tick " << n;
  EXPECT_EQ(s.counters().derated, 0u);
}

// While the watchdog holds the force at zero (no model yet), the motors are
// not heating: 2 s of a 2 N request without a model leave the average at 0.
TEST(ContinuousForceLimit, AForceHeldAtZeroByTheWatchdogDoesNotCount) {
  ForceSafety s = ContinuousLimitOnly();
  for (int n = 0; n < 2000; ++n) s.Apply({0, 0, 2.0}, -1.0, kDt);
  EXPECT_EQ(s.average_force_N(), 0.0);
  EXPECT_EQ(s.Apply({0, 0, 2.0}, 0.001, kDt).z(), 2.0);
}

// A device that reports its continuous force is held to its own rating.
TEST(ContinuousForceLimit, ADeviceRatingReplacesTheDefault) {
  DeviceLimits rated;
  rated.max_continuous_force_N = 1.2;
  ForceSafety s = ContinuousLimitOnly(rated);
  double f_N = 0.0;
  for (int n = 1; n <= 10000; ++n) f_N = s.Apply({0, 0, 2.0}, 0.001, kDt).z();
  EXPECT_NEAR(f_N, ClosedFormOutput(2.0, 1.2, 10000), 1e-9);
  EXPECT_NEAR(f_N, 1.2, 1e-4);
}

}  // namespace
}  // namespace hapsim::bridge::continuous_force_limit_test
