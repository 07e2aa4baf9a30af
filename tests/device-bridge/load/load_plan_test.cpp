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
