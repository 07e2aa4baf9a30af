// ShutdownDeadline: a teardown that blocks for good ends the process at the
// deadline with the code it meant to return; one that finishes disarms it.
#include "hapsim/common/shutdown_deadline.h"

#include <gtest/gtest.h>

#include <chrono>
#include <thread>

namespace hapsim::common {
namespace {

TEST(ShutdownDeadline, ATeardownThatNeverEndsExitsWithTheIntendedCodeAtTheDeadline) {
  EXPECT_EXIT(
      {
        ShutdownDeadline deadline("prog");
        deadline.set_exit_code(3);
        deadline.Arm(0.2);
        std::this_thread::sleep_for(std::chrono::seconds(30));  // a join that never returns
      },
      ::testing::ExitedWithCode(3), "prog: teardown did not finish within 0.2 s");
}

TEST(ShutdownDeadline, ATeardownThatFinishesInTimeDisarmsIt) {
  const auto start = std::chrono::steady_clock::now();
  {
    ShutdownDeadline deadline("prog");
    deadline.set_exit_code(7);  // had it fired, this test process would end with 7: a failure
    deadline.Arm(0.3);
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  }  // disarmed here: the process goes on
  std::this_thread::sleep_for(std::chrono::milliseconds(400));
  EXPECT_LT(std::chrono::steady_clock::now() - start, std::chrono::seconds(5));
}

TEST(ShutdownDeadline, NeverArmedCostsNothing) {
  ShutdownDeadline deadline("prog");
  deadline.set_exit_code(1);
  EXPECT_EQ(deadline.exit_code(), 1);
}

}  // namespace
}  // namespace hapsim::common
