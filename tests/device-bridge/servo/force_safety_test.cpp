// The force path's safety layer: these are safety features, so each rule has
// a test with exact expected numbers.
#include "hapsim/servo/force_safety.h"

#include <gtest/gtest.h>

#include <cmath>
#include <initializer_list>
#include <limits>

#include "safety_test_setup.h"

namespace hapsim::bridge {
namespace {

constexpr double kDt = 0.001;

using test::WithoutRampIn;

// A safety layer whose rise limit (and ramp-in) is out of the way, to test the other rules alone.
ForceSafety NoRiseLimit(SafetyConfig c = WithoutRampIn()) {
  c.max_rise_N_per_s = 1e9;
  return ForceSafety(c);
}

TEST(ForceSafety, ClampsMagnitudeKeepingDirection) {
  auto s = NoRiseLimit();
  const Eigen::Vector3d f = s.Apply({3.0, 0.0, 4.0}, 0.001, kDt);  // |F| = 5 N
  EXPECT_NEAR(f.norm(), 2.5, 1e-12);
  EXPECT_NEAR(f.x() / f.z(), 0.75, 1e-12);
  EXPECT_EQ(s.counters().clamped, 1u);
}

TEST(ForceSafety, NonFiniteForceBecomesZero) {
  auto s = NoRiseLimit();
  EXPECT_EQ(s.Apply({std::nan(""), 0, 0}, 0.001, kDt).norm(), 0.0);
  EXPECT_EQ(s.Apply({std::numeric_limits<double>::infinity(), 0, 0}, 0.001, kDt).norm(), 0.0);
  EXPECT_EQ(s.counters().non_finite, 2u);
}

TEST(ForceSafety, NoModelMeansNoForce) {
  auto s = NoRiseLimit();
  EXPECT_EQ(s.Apply({0, 0, 1.0}, -1.0, kDt).norm(), 0.0);
  EXPECT_EQ(s.state(), WatchdogState::kNoModel);
}

TEST(ForceSafety, WatchdogWarnsThenFadesLinearlyThenDisarms) {
  auto s = NoRiseLimit();
  const Eigen::Vector3d one(0, 0, 1.0);
  EXPECT_NEAR(s.Apply(one, 0.010, kDt).z(), 1.0, 1e-12);
  EXPECT_EQ(s.state(), WatchdogState::kFresh);
  EXPECT_NEAR(s.Apply(one, 0.030, kDt).z(), 1.0, 1e-12);  // warn: full force
  EXPECT_EQ(s.state(), WatchdogState::kWarn);
  EXPECT_NEAR(s.Apply(one, 0.050, kDt).z(), 1.0, 1e-12);  // fade starts at 50 ms
  EXPECT_NEAR(s.Apply(one, 0.075, kDt).z(), 0.5, 1e-12);  // halfway to 100 ms
  EXPECT_EQ(s.state(), WatchdogState::kFading);
  EXPECT_NEAR(s.Apply(one, 0.090, kDt).z(), 0.2, 1e-12);
  EXPECT_EQ(s.Apply(one, 0.100, kDt).norm(), 0.0);
  EXPECT_EQ(s.state(), WatchdogState::kDisarmed);
  EXPECT_EQ(s.counters().disarms, 1u);
}

// A server that promised a model at least every 25 ms (deadband
// keep-alives): the warning comes at 45 ms and the fade starts at 75 ms, but
// the force is still zero and disarmed at 100 ms — a promise never delays
// the zero.
TEST(ForceSafety, APromisedGapMovesTheWarningAndTheFadeButNeverTheZero) {
  auto s = NoRiseLimit();
  const auto at = [&](double gap_s) {
    SafetyInput in;
    in.requested_W_N = Eigen::Vector3d(0, 0, 1.0);
    in.model_age_s = gap_s;
    in.model_gap_allowance_s = 0.025;
    in.dt_s = kDt;
    return s.Apply(in).z();
  };
  EXPECT_NEAR(at(0.044), 1.0, 1e-12);
  EXPECT_EQ(s.state(), WatchdogState::kFresh);
  EXPECT_NEAR(at(0.046), 1.0, 1e-12);
  EXPECT_EQ(s.state(), WatchdogState::kWarn);
  EXPECT_NEAR(at(0.080), 0.8, 1e-12);  // (100 - 80) / (100 - 75)
  EXPECT_EQ(s.state(), WatchdogState::kFading);
  EXPECT_EQ(at(0.100), 0.0);
  EXPECT_EQ(s.state(), WatchdogState::kDisarmed);
  EXPECT_EQ(s.counters().warnings, 1u);
}

// Watchdog events after one tick per model age, each asking for 1 N.
SafetyCounters EventsAfterAges(std::initializer_list<double> ages_s) {
  auto s = NoRiseLimit();
  for (const double age_s : ages_s) s.Apply({0, 0, 1.0}, age_s, kDt);
  return s.counters();
}

TEST(ForceSafety, CountsEachWatchdogEscalationOnceWhileItLasts) {
  const SafetyCounters c = EventsAfterAges({0.001, 0.030, 0.031, 0.060, 0.070, 0.120, 0.130});
  EXPECT_EQ(c.warnings, 1u);
  EXPECT_EQ(c.fades, 1u);
  EXPECT_EQ(c.disarms, 1u);
}

TEST(ForceSafety, AStallThatJumpsFromFreshToDisarmedCountsEveryStatePassed) {
  const SafetyCounters c = EventsAfterAges({0.001, 0.250});
  EXPECT_EQ(c.warnings, 1u);
  EXPECT_EQ(c.fades, 1u);
  EXPECT_EQ(c.disarms, 1u);
}

TEST(ForceSafety, EachReturnToStaleIsANewWarningEvent) {
  const SafetyCounters c = EventsAfterAges({0.001, 0.025, 0.001, 0.025, 0.026, 0.001});
  EXPECT_EQ(c.warnings, 2u);
  EXPECT_EQ(c.fades, 0u);
  EXPECT_EQ(c.disarms, 0u);
}

TEST(ForceSafety, StaysDisarmedUntilAFreshModelThenRampsUp) {
  SafetyConfig c = WithoutRampIn();  // default rise limit 50 N/s
  ForceSafety s(c);
  const Eigen::Vector3d one(0, 0, 1.0);
  s.Apply(one, 0.150, kDt);
  ASSERT_EQ(s.state(), WatchdogState::kDisarmed);
  // A model of 60 ms age would fade, not re-arm: still zero.
  EXPECT_EQ(s.Apply(one, 0.060, kDt).norm(), 0.0);
  EXPECT_EQ(s.state(), WatchdogState::kDisarmed);
  // A fresh model re-arms, but the force ramps at 50 N/s: 0.05 N per ms.
  EXPECT_NEAR(s.Apply(one, 0.001, kDt).z(), 0.05, 1e-12);
  EXPECT_NEAR(s.Apply(one, 0.001, kDt).z(), 0.10, 1e-12);
  for (int i = 0; i < 30; ++i) s.Apply(one, 0.001, kDt);
  EXPECT_NEAR(s.Apply(one, 0.001, kDt).z(), 1.0, 1e-12);  // reached after 20 ms
}

TEST(ForceSafety, DecreasesPassImmediately) {
  ForceSafety s(WithoutRampIn());
  const Eigen::Vector3d big(0, 0, 2.0);
  for (int i = 0; i < 100; ++i) s.Apply(big, 0.001, kDt);
  ASSERT_NEAR(s.Apply(big, 0.001, kDt).z(), 2.0, 1e-12);
  EXPECT_EQ(s.Apply(Eigen::Vector3d::Zero(), 0.001, kDt).norm(), 0.0);
}

TEST(ForceSafety, RejectsBadConfig) {
  SafetyConfig c;
  c.max_force_N = -1;
  EXPECT_THROW(ValidateSafetyConfig(c), std::invalid_argument);
  c = {};
  c.fade_start_age_s = 0.2;  // after disarm
  EXPECT_THROW(ValidateSafetyConfig(c), std::invalid_argument);
}

}  // namespace
}  // namespace hapsim::bridge
