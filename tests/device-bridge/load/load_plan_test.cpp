// Which devices hapsim-load runs: ids, sessions, seeds and phases per device.
#include "hapsim/load/load_plan.h"

#include <gtest/gtest.h>

#include <stdexcept>

namespace hapsim::bridge {
namespace {

TEST(LoadPlan, DeviceIDrivesPrefixedSessionIWithIdSeedAndPhaseOffsetByI) {
  LoadPlanOptions o;
  o.devices = 4;
  o.session_prefix = "class-";
  o.first_device_id = 500;
  o.script.seed = 10;
  o.phase_spread_s = 2.0;
  const auto plan = PlanDevices(o);
  ASSERT_EQ(plan.size(), 4u);
  EXPECT_EQ(plan[3].session, "class-3");
  EXPECT_EQ(plan[3].device_id, 503u);
  EXPECT_EQ(plan[3].script.seed, 13u);
  EXPECT_DOUBLE_EQ(plan[0].phase_s, 0.0);
  EXPECT_DOUBLE_EQ(plan[3].phase_s, 1.5);
}

TEST(LoadPlan, AnExplicitSessionListSetsTheDeviceCount) {
  LoadPlanOptions o;
  o.sessions = SplitCommaList("a,,b");
  const auto plan = PlanDevices(o);
  ASSERT_EQ(plan.size(), 2u);
  EXPECT_EQ(plan[1].session, "b");
  EXPECT_EQ(plan[1].device_id, o.first_device_id + 1);
}

TEST(LoadPlan, DeviceClocksSpreadOverThePeriodAndOverTheRateRange) {
  LoadPlanOptions o;
  o.devices = 5;
  o.period_s = 1e-3;
  o.clock_phase_spread = 1.0;
  o.clock_rate_ppm = 400.0;
  const auto plan = PlanDevices(o);
  ASSERT_TRUE(HasOwnClocks(plan));
  for (std::size_t i = 0; i < plan.size(); ++i) {
    EXPECT_DOUBLE_EQ(plan[i].clock_phase_s, 2e-4 * static_cast<double>(i));  // i / 5 of 1 ms
    EXPECT_DOUBLE_EQ(plan[i].clock_rate_ppm, -400.0 + 200.0 * static_cast<double>(i));
  }
  o.clock_phase_spread = 0.0;
  o.clock_rate_ppm = 0.0;
  EXPECT_FALSE(HasOwnClocks(PlanDevices(o)));
  o.devices = 1;
  o.clock_rate_ppm = 400.0;
  EXPECT_EQ(PlanDevices(o)[0].clock_rate_ppm, 0.0);  // one device: the nominal rate
}

TEST(LoadPlan, ClockOptionsOutOfRangeAreRefused) {
  LoadPlanOptions o;
  o.clock_phase_spread = 1.5;
  EXPECT_THROW(PlanDevices(o), std::invalid_argument);
  o.clock_phase_spread = -0.1;
  EXPECT_THROW(PlanDevices(o), std::invalid_argument);
  o.clock_phase_spread = 0.5;
  o.clock_rate_ppm = 20000.0;
  EXPECT_THROW(PlanDevices(o), std::invalid_argument);
  o.clock_rate_ppm = -1.0;
  EXPECT_THROW(PlanDevices(o), std::invalid_argument);
}

TEST(LoadPlan, RejectsRepeatedOrMalformedSessionsAndBadCounts) {
  LoadPlanOptions o;
  o.sessions = {"a", "a"};
  EXPECT_THROW(PlanDevices(o), std::invalid_argument);
  o.sessions = {"has space"};
  EXPECT_THROW(PlanDevices(o), std::invalid_argument);
  o.sessions = {};
  o.devices = 0;
  EXPECT_THROW(PlanDevices(o), std::invalid_argument);
}

}  // namespace
}  // namespace hapsim::bridge
