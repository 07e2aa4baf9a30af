// The limits the chain enforces for a device: the lower of the configured
// and the reported value (the continuous force: the device's own rating),
// and every limit refused with its name when out of range.
#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <string>
#include <vector>

#include "hapsim/servo/force_safety.h"
#include "safety_test_setup.h"

// Its own namespace: the test files are compiled in batches (unity build).
namespace hapsim::bridge::safety_limits_test {
namespace {

constexpr double kDt = 0.001;

TEST(SafetyLimits, AnUnknownDeviceGetsTheConfiguredLimits) {
  const EffectiveLimits e = CombineLimits(SafetyConfig{}, DeviceLimits{});
  EXPECT_EQ(e.max_force_N, 2.5);
  EXPECT_EQ(e.max_continuous_force_N, 0.88);
  EXPECT_EQ(e.max_stiffness_N_per_m, 700.0);  // CHAI3D's PHANTOM Omni
  EXPECT_EQ(e.max_damping_Ns_per_m, 5.0);
}

TEST(SafetyLimits, AReportedLimitLowersTheConfiguredOneNeverRaisesIt) {
  DeviceLimits touch;  // CHAI3D's Touch: 3.3 N, 400 N/m, 4 N·s/m
  touch.max_force_N = 3.3;
  touch.max_stiffness_N_per_m = 400.0;
  touch.max_damping_Ns_per_m = 4.0;
  const EffectiveLimits e = CombineLimits(SafetyConfig{}, touch);
  EXPECT_EQ(e.max_force_N, 2.5);  // 3.3 reported, 2.5 configured
  EXPECT_EQ(e.max_stiffness_N_per_m, 400.0);
  EXPECT_EQ(e.max_damping_Ns_per_m, 4.0);
  DeviceLimits weak;
  weak.max_force_N = 2.0;
  EXPECT_EQ(CombineLimits(SafetyConfig{}, weak).max_force_N, 2.0);
}

TEST(SafetyLimits, TheContinuousForceIsTheDevicesOwnRatingWhenItHasOne) {
  DeviceLimits rated;
  rated.max_continuous_force_N = 1.2;
  EXPECT_EQ(CombineLimits(SafetyConfig{}, rated).max_continuous_force_N, 1.2);
  rated.max_continuous_force_N = 0.5;
  EXPECT_EQ(CombineLimits(SafetyConfig{}, rated).max_continuous_force_N, 0.5);
}

TEST(SafetyLimits, TheClampIsTheDevicesPeakWhenThatIsLower) {
  DeviceLimits weak;
  weak.max_force_N = 2.0;
  ForceSafety s(test::QuietChain(), weak);
  const Eigen::Vector3d f = s.Apply({0.0, 3.0, 4.0}, 0.001, kDt);  // |F| = 5 N
  EXPECT_NEAR(f.norm(), 2.0, 1e-12);
  EXPECT_NEAR(f.y() / f.z(), 0.75, 1e-12);
  EXPECT_EQ(s.counters().clamped, 1u);
}

// Each new limit out of range is refused, and the message names it.
TEST(SafetyLimits, EachLimitOutOfRangeIsRefusedByName) {
  const std::vector<std::pair<std::string, std::function<void(SafetyConfig&)>>> bad = {
      {"max_stiffness_N_per_m", [](SafetyConfig& c) { c.max_stiffness_N_per_m = 0.0; }},
      {"max_damping_Ns_per_m", [](SafetyConfig& c) { c.max_damping_Ns_per_m = -1.0; }},
      {"max_velocity_m_per_s", [](SafetyConfig& c) { c.max_velocity_m_per_s = std::nan(""); }},
      {"max_continuous_force_N", [](SafetyConfig& c) { c.max_continuous_force_N = -0.88; }},
      {"continuous_window_s", [](SafetyConfig& c) { c.continuous_window_s = 0.0; }},
      {"ramp_in_s", [](SafetyConfig& c) { c.ramp_in_s = -0.1; }},
      {"model_transition_ticks", [](SafetyConfig& c) { c.model_transition_ticks = -1; }},
      {"jnd_fraction", [](SafetyConfig& c) { c.jnd_fraction = 1.5; }},
      {"jnd_floor_N", [](SafetyConfig& c) { c.jnd_floor_N = 0.0; }},
  };
  for (const auto& [name, spoil] : bad) {
    SafetyConfig c;
    spoil(c);
    try {
      ValidateSafetyConfig(c);
      ADD_FAILURE() << name << " accepted";
    } catch (const std::invalid_argument& e) {
      EXPECT_NE(std::string(e.what()).find(name), std::string::npos) << e.what();
    }
    EXPECT_THROW(ForceSafety{c}, std::invalid_argument) << name;
  }
  EXPECT_NO_THROW(ValidateSafetyConfig(SafetyConfig{}));
}

// --max-force-n below the default continuous limit (0.88 N) stays valid:
// the clamp then keeps every average under it.
TEST(SafetyLimits, AClampBelowTheContinuousLimitIsValid) {
  SafetyConfig c;
  c.max_force_N = 0.5;
  EXPECT_NO_THROW(ValidateSafetyConfig(c));
}

TEST(SafetyLimits, AGarbageDeviceLimitIsRefusedByName) {
  DeviceLimits d;
  d.max_damping_Ns_per_m = -4.0;
  try {
    ValidateDeviceLimits(d);
    ADD_FAILURE() << "accepted";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("max_damping_Ns_per_m"), std::string::npos) << e.what();
  }
  d = {};
  d.max_force_N = std::nan("");
  EXPECT_THROW((ForceSafety{SafetyConfig{}, d}), std::invalid_argument);
  EXPECT_NO_THROW(ValidateDeviceLimits(DeviceLimits{}));  // all unknown
}

}  // namespace
}  // namespace hapsim::bridge::safety_limits_test
