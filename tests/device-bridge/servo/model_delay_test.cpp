// ModelDelay: the measurement aid that makes the bridge see every model a
// set time late, as a longer link would.
#include "hapsim/servo/model_delay.h"

#include <gtest/gtest.h>

namespace hapsim::bridge {
namespace {

constexpr std::int64_t kMs = 1'000'000;

ReceivedModel ModelArrivingAt(std::int64_t received_ns, std::uint64_t seq) {
  ReceivedModel m;
  m.received_ns = received_ns;
  m.seq = seq;
  return m;
}

TEST(ModelDelay, AModelIsReleasedExactlyTheDelayAfterItArrivedWithItsArrivalMovedThere) {
  ModelDelay delay(0.050);
  common::LatestValue<ReceivedModel> inbox;
  ReceivedModel out;
  inbox.Publish(ModelArrivingAt(10 * kMs, 1));
  EXPECT_FALSE(delay.Take(inbox, 10 * kMs, &out));
  EXPECT_FALSE(delay.Take(inbox, 60 * kMs - 1, &out));  // 1 ns early
  ASSERT_TRUE(delay.Take(inbox, 60 * kMs, &out));
  EXPECT_EQ(out.seq, 1u);
  EXPECT_EQ(out.received_ns, 60 * kMs);  // its age counts from when the longer link would deliver it
  EXPECT_FALSE(delay.Take(inbox, 61 * kMs, &out));  // released once
}

TEST(ModelDelay, OfSeveralDueModelsTheNewestIsTakenAndNoneLater) {
  ModelDelay delay(0.100);
  common::LatestValue<ReceivedModel> inbox;
  ReceivedModel out;
  for (std::uint64_t k = 0; k < 5; ++k) {  // one per ms, taken each tick
    inbox.Publish(ModelArrivingAt(static_cast<std::int64_t>(k) * kMs, k));
    EXPECT_FALSE(delay.Take(inbox, static_cast<std::int64_t>(k) * kMs, &out));
  }
  ASSERT_TRUE(delay.Take(inbox, 103 * kMs, &out));  // models 0-3 due: the newest
  EXPECT_EQ(out.seq, 3u);
  ASSERT_TRUE(delay.Take(inbox, 104 * kMs, &out));
  EXPECT_EQ(out.seq, 4u);
  EXPECT_EQ(delay.dropped(), 0u);
}

TEST(ModelDelay, AFullRingDropsTheOldestAndCountsIt) {
  ModelDelay delay(0.5, 4);
  common::LatestValue<ReceivedModel> inbox;
  ReceivedModel out;
  for (std::uint64_t k = 0; k < 6; ++k) {
    inbox.Publish(ModelArrivingAt(static_cast<std::int64_t>(k) * kMs, k));
    delay.Take(inbox, static_cast<std::int64_t>(k) * kMs, &out);
  }
  EXPECT_EQ(delay.dropped(), 2u);
  ASSERT_TRUE(delay.Take(inbox, 502 * kMs, &out));
  EXPECT_EQ(out.seq, 2u);  // 0 and 1 were pushed out
}

TEST(ModelDelay, ZeroIsOffAndOutOfRangeIsRefused) {
  EXPECT_FALSE(ModelDelay(0.0).enabled());
  EXPECT_TRUE(ModelDelay(0.001).enabled());
  EXPECT_THROW(ModelDelay(-0.001), std::invalid_argument);
  EXPECT_THROW(ModelDelay(1.5), std::invalid_argument);
}

}  // namespace
}  // namespace hapsim::bridge
