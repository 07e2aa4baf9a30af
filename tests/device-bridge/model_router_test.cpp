// hapsim-load's per-device dispatch: a model reaches exactly the inbox of
// the device (and session) it names; anything else is counted and dropped.
#include "hapsim/bridge/model_router.h"

#include <cstring>

#include <gtest/gtest.h>

namespace hapsim::bridge {
namespace {

hapsim_dds_LocalForceModel ModelFor(std::uint32_t device_id, const char* session, std::uint64_t seq) {
  hapsim_dds_LocalForceModel m{};
  m.device_id = device_id;
  std::strncpy(m.session, session, sizeof m.session - 1);
  m.seq = seq;
  return m;
}

class ModelRouterTest : public ::testing::Test {
 protected:
  ModelRouter router_{100, {"room-a", "room-b", "room-c"}};

  bool HasNew(std::size_t device, ReceivedModel* out) { return router_.inbox(device).TakeIfNew(out); }
};

TEST_F(ModelRouterTest, AModelForDeviceJLandsOnlyInJsInboxWithItsArrivalStamp) {
  router_.Route(ModelFor(101, "room-b", 42), 123456789);
  ReceivedModel got;
  ASSERT_TRUE(HasNew(1, &got));
  EXPECT_EQ(got.msg.seq, 42u);
  EXPECT_EQ(got.received_ns, 123456789);
  EXPECT_FALSE(HasNew(0, &got));
  EXPECT_FALSE(HasNew(2, &got));
  EXPECT_EQ(router_.models_routed(1), 1u);
  EXPECT_EQ(router_.models_routed(0), 0u);
}

TEST_F(ModelRouterTest, AModelForAnUnknownDeviceIsCountedAndReachesNoInbox) {
  router_.Route(ModelFor(99, "room-a", 1), 1);   // below the first id
  router_.Route(ModelFor(103, "room-a", 1), 1);  // past the last
  EXPECT_EQ(router_.models_for_unknown_devices(), 2u);
  ReceivedModel got;
  for (std::size_t i = 0; i < router_.devices(); ++i) EXPECT_FALSE(HasNew(i, &got)) << "device " << i;
}

TEST_F(ModelRouterTest, AModelForOurDeviceButAnotherSessionIsCountedAndDropped) {
  router_.Route(ModelFor(100, "room-b", 1), 1);
  EXPECT_EQ(router_.models_for_other_sessions(), 1u);
  EXPECT_EQ(router_.models_for_unknown_devices(), 0u);
  ReceivedModel got;
  EXPECT_FALSE(HasNew(0, &got));
}

TEST_F(ModelRouterTest, TheNewestModelOfADeviceWins) {
  router_.Route(ModelFor(102, "room-c", 1), 1);
  router_.Route(ModelFor(102, "room-c", 2), 2);
  ReceivedModel got;
  ASSERT_TRUE(HasNew(2, &got));
  EXPECT_EQ(got.msg.seq, 2u);
  EXPECT_EQ(router_.models_routed(2), 2u);
}

}  // namespace
}  // namespace hapsim::bridge
