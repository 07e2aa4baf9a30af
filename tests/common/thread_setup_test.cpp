// Real-time priority by thread name: exactly the named threads change
// policy (SCHED_FIFO at the asked priority) when the kernel permits it, and
// a refusal is reported, leaving the thread as it was.
#include "hapsim/common/thread_setup.h"

#include <gtest/gtest.h>
#include <pthread.h>
#include <sched.h>

#include <atomic>
#include <thread>

namespace hapsim::common {
namespace {

// A thread that waits until told to end.
class IdleThread {
 public:
  explicit IdleThread(const char* name)
      : thread_([this] {
          while (!stop_.load()) std::this_thread::sleep_for(std::chrono::milliseconds(1));
        }) {
    NameThread(thread_, name);
  }
  ~IdleThread() {
    stop_ = true;
    thread_.join();
  }
  int Policy(int* priority) {
    sched_param param{};
    int policy = -1;
    pthread_getschedparam(thread_.native_handle(), &policy, &param);
    *priority = param.sched_priority;
    return policy;
  }

 private:
  std::atomic<bool> stop_{false};
  std::thread thread_;
};

TEST(RaiseThreadsNamed, OnlyTheNamedThreadsBecomeFifoAtThePriorityOrTheRefusalIsReported) {
  IdleThread tick("rt-probe-tick"), other("rt-probe-other");
  const RealtimeResult r = RaiseThreadsNamed({"rt-probe-tick"}, 7);
  ASSERT_EQ(r.raised + r.refused, 1);  // found by name, once
  int priority = 0;
  if (r.raised == 1) {
    EXPECT_EQ(tick.Policy(&priority), SCHED_FIFO);
    EXPECT_EQ(priority, 7);
  } else {
    EXPECT_EQ(tick.Policy(&priority), SCHED_OTHER);  // refused: unchanged
  }
  EXPECT_EQ(other.Policy(&priority), SCHED_OTHER);
  EXPECT_EQ(priority, 0);
}

TEST(RaiseThreadsNamed, NoThreadOfThatNameIsNeitherRaisedNorRefused) {
  const RealtimeResult r = RaiseThreadsNamed({"no-such-thread"}, 7);
  EXPECT_EQ(r.raised, 0);
  EXPECT_EQ(r.refused, 0);
}

}  // namespace
}  // namespace hapsim::common
