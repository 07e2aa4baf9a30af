// The servo threads' clock wakes on absolute deadlines: never early, so N
// periods take at least N periods whatever each sleep overshoots.
#include "hapsim/servo/deadline_ticker.h"

#include <gtest/gtest.h>

namespace hapsim::bridge {
namespace {

TEST(DeadlineTicker, TheNthWakeIsNoEarlierThanNPeriodsAfterTheFirst) {
  DeadlineTicker ticker(1000.0, 64);
  const double first_s = ticker.Wait();
  double last_s = first_s;
  for (int i = 0; i < 20; ++i) last_s = ticker.Wait();
  EXPECT_GE(last_s - first_s, 0.020 - 1e-6);
  EXPECT_EQ(ticker.wakes(), 21u);
  EXPECT_EQ(ticker.PeriodError().count, 20u);
  EXPECT_GE(ticker.Lateness().min, 0.0);
}

}  // namespace
}  // namespace hapsim::bridge
