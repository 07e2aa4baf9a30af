// DeviceOwnership: one device drives a session until it goes quiet.
#include "hapsim/service/device_ownership.h"

#include <gtest/gtest.h>

namespace hapsim::service {
namespace {

constexpr std::int64_t kTimeoutNs = 250'000'000;

TEST(DeviceOwnership, TheFirstDeviceToStreamOwnsTheSession) {
  DeviceOwnership o(kTimeoutNs);
  EXPECT_FALSE(o.has_owner());
  EXPECT_TRUE(o.Accept(7, 1'000));
  EXPECT_TRUE(o.has_owner());
  EXPECT_EQ(o.owner(), 7u);
  EXPECT_TRUE(o.Accept(7, 2'000));
}

TEST(DeviceOwnership, ASecondDeviceIsRefusedWhileTheOwnerStreams) {
  DeviceOwnership o(kTimeoutNs);
  ASSERT_TRUE(o.Accept(7, 0));
  EXPECT_FALSE(o.Accept(8, 1'000'000));
  EXPECT_TRUE(o.Accept(7, 2'000'000));
  // Exactly at the timeout the owner still holds it.
  EXPECT_FALSE(o.Accept(8, 2'000'000 + kTimeoutNs));
  EXPECT_EQ(o.owner(), 7u);
}

TEST(DeviceOwnership, AnotherDeviceTakesOverOnceTheOwnerIsSilentForTheTimeout) {
  DeviceOwnership o(kTimeoutNs);
  ASSERT_TRUE(o.Accept(7, 0));
  EXPECT_TRUE(o.Accept(8, kTimeoutNs + 1));
  EXPECT_EQ(o.owner(), 8u);
  EXPECT_FALSE(o.Accept(7, kTimeoutNs + 2));  // the old owner is now the intruder
}

}  // namespace
}  // namespace hapsim::service
