// DeviceOwnership: one device drives a session until it goes quiet, and only
// its new poses (seq rising) count.
#include "hapsim/runtime/device_ownership.h"

#include <gtest/gtest.h>

namespace hapsim::service {
namespace {

constexpr std::int64_t kTimeoutNs = 250'000'000;
constexpr PoseVerdict kOk = PoseVerdict::kAccepted;

TEST(DeviceOwnership, TheFirstDeviceToStreamOwnsTheSession) {
  DeviceOwnership o(kTimeoutNs);
  EXPECT_FALSE(o.has_owner());
  EXPECT_EQ(o.Accept(7, 0, 1'000), kOk);
  EXPECT_TRUE(o.has_owner());
  EXPECT_EQ(o.owner(), 7u);
  EXPECT_EQ(o.Accept(7, 1, 2'000), kOk);
}

TEST(DeviceOwnership, ASecondDeviceIsRefusedWhileTheOwnerStreams) {
  DeviceOwnership o(kTimeoutNs);
  ASSERT_EQ(o.Accept(7, 10, 0), kOk);
  EXPECT_EQ(o.Accept(8, 500, 1'000'000), PoseVerdict::kOtherDevice);
  EXPECT_EQ(o.Accept(7, 11, 2'000'000), kOk);
  // Exactly at the timeout the owner still holds it.
  EXPECT_EQ(o.Accept(8, 501, 2'000'000 + kTimeoutNs), PoseVerdict::kOtherDevice);
  EXPECT_EQ(o.owner(), 7u);
}

TEST(DeviceOwnership, AnotherDeviceTakesOverOnceTheOwnerIsSilentForTheTimeout) {
  DeviceOwnership o(kTimeoutNs);
  ASSERT_EQ(o.Accept(7, 10, 0), kOk);
  EXPECT_EQ(o.Accept(8, 0, kTimeoutNs + 1), kOk);
  EXPECT_EQ(o.owner(), 8u);
  EXPECT_EQ(o.Accept(7, 11, kTimeoutNs + 2), PoseVerdict::kOtherDevice);  // the old owner is now the intruder
}

TEST(DeviceOwnership, ADuplicateOrReorderedPoseFromTheOwnerIsStale) {
  DeviceOwnership o(kTimeoutNs);
  ASSERT_EQ(o.Accept(7, 100, 0), kOk);
  EXPECT_EQ(o.Accept(7, 100, 1'000), PoseVerdict::kStale);  // duplicate
  EXPECT_EQ(o.Accept(7, 99, 2'000), PoseVerdict::kStale);   // arrived after 100
  EXPECT_EQ(o.Accept(7, 102, 3'000), kOk);                  // a gap is fine: samples may be lost
  EXPECT_EQ(o.Accept(7, 101, 4'000), PoseVerdict::kStale);
}

TEST(DeviceOwnership, TwoBridgesWithTheSameDeviceIdDoNotInterleave) {
  // Bridge A has streamed for 5 s (seq ~5000); bridge B starts with the same
  // --device-id: B's poses are refused while A streams, so only A drives.
  DeviceOwnership o(kTimeoutNs);
  std::int64_t t = 0;
  std::uint64_t seq_a = 5000, seq_b = 0;
  int accepted_a = 0, accepted_b = 0;
  for (int i = 0; i < 1000; ++i, t += 1'000'000) {
    if (o.Accept(7, seq_a++, t) == kOk) ++accepted_a;
    if (o.Accept(7, seq_b++, t + 500'000) == kOk) ++accepted_b;
  }
  EXPECT_EQ(accepted_a, 1000);
  EXPECT_EQ(accepted_b, 0);
}

TEST(DeviceOwnership, ABridgeRestartedWithTheSameIdOwnsAgainAfterTheTimeout) {
  DeviceOwnership o(kTimeoutNs);
  ASSERT_EQ(o.Accept(7, 9000, 0), kOk);
  // Restarted quickly: its seq starts again at 0, stale while the old stream
  // might still be alive...
  EXPECT_EQ(o.Accept(7, 0, 100'000'000), PoseVerdict::kStale);
  // ...and accepted once the old stream has been silent for the timeout.
  EXPECT_EQ(o.Accept(7, 150, kTimeoutNs + 1), kOk);
  EXPECT_EQ(o.Accept(7, 151, kTimeoutNs + 2), kOk);
}

}  // namespace
}  // namespace hapsim::service
