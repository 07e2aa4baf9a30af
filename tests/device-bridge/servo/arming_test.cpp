// Arming: after each arming (the first model, a fresh model after the
// watchdog disarmed, a press of the arm button) the clamp rises linearly
// from 0 to 2.5 N over 0.5 s: 0.005 N per 1 ms tick. The arm button toggles
// armed on each press; disarmed, the force is exactly zero.
#include "hapsim/servo/arming.h"

#include <gtest/gtest.h>

#include <algorithm>

#include "hapsim/servo/force_safety.h"
#include "safety_test_setup.h"

// Its own namespace: the test files are compiled in batches (unity build).
namespace hapsim::bridge::arming_test {
namespace {

constexpr double kDt = 0.001;
constexpr double kRampNPerTick = 2.5 * kDt / 0.5;  // 0.005 N

SafetyConfig RampInOnly() {
  SafetyConfig c = test::QuietChain();
  c.ramp_in_s = SafetyConfig{}.ramp_in_s;
  return c;
}

SafetyInput Fresh(double request_N, std::uint32_t buttons = 0) {
  SafetyInput in;
  in.requested_W_N = Eigen::Vector3d(0, 0, request_N);
  in.buttons = buttons;
  in.model_age_s = 0.001;
  in.dt_s = kDt;
  return in;
}

// 1.234 N asked from the first model on: the clamp allows 0.005 k N on the
// k-th tick, so the force is the clamp until tick 246 (1.23 N) and the
// request from tick 247 (1.235 N allowed) on; 246 ticks counted.
TEST(RampIn, TheClampRisesLinearlyOverHalfASecondAfterTheFirstModel) {
  ASSERT_EQ(SafetyConfig{}.ramp_in_s, 0.5);
  ForceSafety s(RampInOnly());
  SafetyInput no_model = Fresh(1.234);
  no_model.model_age_s = -1.0;
  for (int n = 0; n < 100; ++n) ASSERT_EQ(s.Apply(no_model).norm(), 0.0);  // the ramp waits for the first model
  for (int k = 1; k <= 600; ++k) {
    const double expected_N = std::min(1.234, k * kRampNPerTick);
    ASSERT_NEAR(s.Apply(Fresh(1.234)).z(), expected_N, 1e-12) << "tick " << k;
  }
  EXPECT_EQ(s.counters().ramp_limited, 246u);
  EXPECT_EQ(s.counters().clamped, 0u);
}

TEST(RampIn, AReArmAfterTheWatchdogDisarmedRampsAgainAFadeDoesNot) {
  ForceSafety s(RampInOnly());
  for (int k = 0; k < 600; ++k) s.Apply(Fresh(2.0));
  ASSERT_NEAR(s.Apply(Fresh(2.0)).z(), 2.0, 1e-12);
  // Fading (60 ms: 80 %) and fresh again: never stopped, no new ramp.
  SafetyInput fading = Fresh(2.0);
  fading.model_age_s = 0.060;
  EXPECT_NEAR(s.Apply(fading).z(), 1.6, 1e-12);
  EXPECT_NEAR(s.Apply(Fresh(2.0)).z(), 2.0, 1e-12);
  // Disarmed by the watchdog, then a fresh model: the ramp starts over.
  SafetyInput stale = Fresh(2.0);
  stale.model_age_s = 0.150;
  EXPECT_EQ(s.Apply(stale).norm(), 0.0);
  ASSERT_EQ(s.state(), WatchdogState::kDisarmed);
  EXPECT_NEAR(s.Apply(Fresh(2.0)).z(), 1 * kRampNPerTick, 1e-12);
  EXPECT_NEAR(s.Apply(Fresh(2.0)).z(), 2 * kRampNPerTick, 1e-12);
}

// Arm button 2 (mask 0b10): disarmed at start; a press arms and ramps in,
// holding or pressing another button changes nothing, the next press
// disarms at once (zero the same tick), the one after arms and ramps again.
TEST(ArmButton, EachPressTogglesArmedAndArmingRampsIn) {
  SafetyConfig c = RampInOnly();
  c.arm_button_mask = 0b10;
  ForceSafety s(c);
  for (int n = 0; n < 10; ++n) ASSERT_EQ(s.Apply(Fresh(1.0)).norm(), 0.0);
  EXPECT_FALSE(s.armed());
  EXPECT_NEAR(s.Apply(Fresh(1.0, 0b10)).z(), 1 * kRampNPerTick, 1e-12);  // press: armed
  EXPECT_TRUE(s.armed());
  for (int k = 2; k <= 10; ++k) ASSERT_NEAR(s.Apply(Fresh(1.0, 0b10)).z(), k * kRampNPerTick, 1e-12);  // held
  EXPECT_NEAR(s.Apply(Fresh(1.0, 0b11)).z(), 11 * kRampNPerTick, 1e-12);  // button 1 too: not the arm button
  EXPECT_NEAR(s.Apply(Fresh(1.0, 0b00)).z(), 12 * kRampNPerTick, 1e-12);  // release
  EXPECT_EQ(s.counters().arm_toggles, 1u);
  EXPECT_EQ(s.Apply(Fresh(1.0, 0b10)).norm(), 0.0);  // press: disarmed, zero at once
  EXPECT_FALSE(s.armed());
  EXPECT_EQ(s.Apply(Fresh(1.0, 0b00)).norm(), 0.0);
  EXPECT_NEAR(s.Apply(Fresh(1.0, 0b10)).z(), 1 * kRampNPerTick, 1e-12);  // press: armed, ramp from 0
  EXPECT_EQ(s.counters().arm_toggles, 3u);
}

TEST(ArmButton, WithoutAnArmButtonTheStylusIsAlwaysArmed) {
  ForceSafety s(test::QuietChain());  // mask 0
  EXPECT_TRUE(s.armed());
  EXPECT_NEAR(s.Apply(Fresh(1.0, 0b11)).z(), 1.0, 1e-12);
  EXPECT_NEAR(s.Apply(Fresh(1.0, 0b00)).z(), 1.0, 1e-12);
  EXPECT_NEAR(s.Apply(Fresh(1.0, 0b11)).z(), 1.0, 1e-12);
  EXPECT_EQ(s.counters().arm_toggles, 0u);
}

}  // namespace
}  // namespace hapsim::bridge::arming_test
