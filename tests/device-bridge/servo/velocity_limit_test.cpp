// The stylus velocity limit: faster than max_velocity_m_per_s (0.6 m/s by
// default), or with a velocity that is not a number, the force is exactly
// zero and counted; below it again, the force returns through the rise
// limit (50 N/s: 0.05 N per 1 ms tick).
#include <gtest/gtest.h>

#include <cmath>

#include "hapsim/servo/force_safety.h"
#include "safety_test_setup.h"

// Its own namespace: the test files are compiled in batches (unity build).
namespace hapsim::bridge::velocity_limit_test {
namespace {

constexpr double kDt = 0.001;

SafetyInput Tick(double speed_m_per_s) {
  SafetyInput in;
  in.requested_W_N = Eigen::Vector3d(0, 0, 1.0);
  in.velocity_W_m_per_s = Eigen::Vector3d(speed_m_per_s, 0, 0);  // across the force: no work, no passivity action
  in.model_age_s = 0.001;
  in.dt_s = kDt;
  return in;
}

TEST(VelocityLimit, AboveTheLimitTheForceIsZeroAndReturnsThroughTheRiseLimit) {
  SafetyConfig c = test::QuietChain();
  c.max_velocity_m_per_s = SafetyConfig{}.max_velocity_m_per_s;
  c.max_rise_N_per_s = SafetyConfig{}.max_rise_N_per_s;
  ASSERT_EQ(c.max_velocity_m_per_s, 0.6);
  ForceSafety s(c);
  for (int i = 0; i < 20; ++i) s.Apply(Tick(0.0));  // ramps to 1 N at 0.05 N/ms
  EXPECT_NEAR(s.Apply(Tick(0.59)).z(), 1.0, 1e-12);
  EXPECT_NEAR(s.Apply(Tick(0.6)).z(), 1.0, 1e-12);  // at the limit: passes
  EXPECT_EQ(s.Apply(Tick(0.61)).norm(), 0.0);
  EXPECT_EQ(s.Apply(Tick(5.0)).norm(), 0.0);
  EXPECT_EQ(s.counters().velocity_limited, 2u);
  // Back under the limit: 0.05 N, then 0.10 N, ... (the rise limit).
  EXPECT_NEAR(s.Apply(Tick(0.5)).z(), 0.05, 1e-12);
  EXPECT_NEAR(s.Apply(Tick(0.5)).z(), 0.10, 1e-12);
  EXPECT_EQ(s.counters().velocity_limited, 2u);
}

TEST(VelocityLimit, ANonFiniteVelocityIsOverTheLimit) {
  ForceSafety s(test::QuietChain());
  EXPECT_EQ(s.Apply(Tick(std::nan(""))).norm(), 0.0);
  EXPECT_EQ(s.counters().velocity_limited, 1u);
  EXPECT_EQ(s.passivity_energy_J(), 0.0);  // and does not poison the passivity observer
  EXPECT_NEAR(s.Apply(Tick(0.0)).z(), 1.0, 1e-12);
}

// Diagonal motion: the limit is on the speed |v|, not on a component.
TEST(VelocityLimit, TheLimitIsOnTheSpeedNotAComponent) {
  SafetyConfig c = test::QuietChain();
  c.max_velocity_m_per_s = 0.6;
  ForceSafety s(c);
  SafetyInput in = Tick(0.0);
  in.velocity_W_m_per_s = Eigen::Vector3d(0.45, 0.45, 0.0);  // |v| = 0.636 m/s, each component 0.45
  EXPECT_EQ(s.Apply(in).norm(), 0.0);
  EXPECT_EQ(s.counters().velocity_limited, 1u);
}

}  // namespace
}  // namespace hapsim::bridge::velocity_limit_test
