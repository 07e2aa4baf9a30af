// The programming-error tier (hapsim/core/assert.h): HAPSIM_DEMAND always
// aborts with the condition and message; HAPSIM_ASSERT only in debug builds,
// and in release it does not even evaluate its condition.
#include "hapsim/core/assert.h"

#include <gtest/gtest.h>

namespace hapsim::core {
namespace {

TEST(AssertDeathTest, DemandAbortsWithConditionFileAndMessage) {
  const int nodes = 3;
  EXPECT_DEATH(HAPSIM_DEMAND(nodes > 5, "need more nodes"),
               "hapsim: .*assert_test.cpp:[0-9]+: HAPSIM_DEMAND failed: nodes > 5: need more nodes");
}

TEST(Assert, PassingChecksDoNothing) {
  int evaluated = 0;
  HAPSIM_DEMAND(++evaluated == 1, "evaluated once");
  EXPECT_EQ(evaluated, 1);
}

TEST(AssertDeathTest, AssertAbortsInDebugAndIsNotEvaluatedInRelease) {
  int evaluated = 0;
#ifdef NDEBUG
  HAPSIM_ASSERT(++evaluated < 0, "never evaluated in release");
  EXPECT_EQ(evaluated, 0);
#else
  EXPECT_DEATH(HAPSIM_ASSERT(evaluated > 0, "debug check"), "HAPSIM_ASSERT failed: evaluated > 0: debug check");
#endif
}

}  // namespace
}  // namespace hapsim::core
