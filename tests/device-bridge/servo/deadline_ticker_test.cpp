// The servo threads' clock wakes on absolute deadlines: never early, so the
// wake after N periods comes at least N periods after the start whatever
// each sleep overshoots. (Not N periods after the first wake: that one is
// due at the start itself, and a preempted thread takes it late.)
#include "hapsim/servo/deadline_ticker.h"

#include <gtest/gtest.h>

namespace hapsim::bridge {
namespace {

TEST(DeadlineTicker, TheWakeAfterNPeriodsIsNoEarlierThanNPeriodsAfterTheStart) {
  DeadlineTicker ticker(1000.0, 64);
  double last_s = ticker.Wait();  // due at the start
  for (int i = 0; i < 20; ++i) last_s = ticker.Wait();
  EXPECT_GE(last_s, 0.020);
  EXPECT_EQ(ticker.wakes(), 21u);
  EXPECT_EQ(ticker.PeriodError().count, 20u);
  EXPECT_GE(ticker.Lateness().min, 0.0);
}

}  // namespace
}  // namespace hapsim::bridge
