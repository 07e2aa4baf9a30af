// TickPool: deadline order, wake-ups, one worker per task, removal — with
// workers that sleep between ticks and with workers that spin.
#include "hapsim/runtime/tick_pool.h"

#include <gtest/gtest.h>
#include <time.h>

#include <atomic>
#include <chrono>
#include <memory>
#include <thread>
#include <vector>

#include "hapsim/common/clock.h"

namespace hapsim::service {
namespace {

using common::SteadyNowNs;
constexpr std::int64_t kMs = 1'000'000;

// Ticks every period_ns on its own deadline and records what it saw.
class PeriodicTask : public TickTask {
 public:
  explicit PeriodicTask(std::int64_t period_ns, std::int64_t work_ns = 0) : period_ns_(period_ns), work_ns_(work_ns) {}
  std::int64_t RunTick(std::int64_t due_ns, std::int64_t now_ns) override {
    if (inside_.exchange(true)) overlaps_.fetch_add(1);
    if (now_ns < earliest_start_vs_due_ns_ + due_ns) early_.fetch_add(1);
    if (work_ns_ > 0) std::this_thread::sleep_for(std::chrono::nanoseconds(work_ns_));
    ticks_.fetch_add(1);
    last_due_ns_.store(due_ns);
    inside_.store(false);
    return period_ns_ > 0 ? due_ns + period_ns_ : kNeverNs;
  }
  std::atomic<int> ticks_{0}, overlaps_{0}, early_{0};
  std::atomic<std::int64_t> last_due_ns_{0};
  std::int64_t earliest_start_vs_due_ns_ = -20'000;  // the pool may start a tick up to its coalescing window early

 private:
  std::int64_t period_ns_, work_ns_;
  std::atomic<bool> inside_{false};
};

bool WaitFor(const std::function<bool()>& done, std::int64_t timeout_ns = 2'000 * kMs) {
  const std::int64_t end = SteadyNowNs() + timeout_ns;
  while (!done()) {
    if (SteadyNowNs() > end) return false;
    std::this_thread::sleep_for(std::chrono::microseconds(200));
  }
  return true;
}

// Every property holds whichever way an idle worker waits.
class TickPoolWaits : public ::testing::TestWithParam<common::IdleWait> {};

TEST_P(TickPoolWaits, NoTickStartsBeforeItIsDue) {
  TickPool pool(2, TickPool::kDefaultCoalesceNs, GetParam());
  std::vector<std::unique_ptr<PeriodicTask>> tasks;
  for (int i = 0; i < 16; ++i) tasks.push_back(std::make_unique<PeriodicTask>(kMs));
  const std::int64_t start = SteadyNowNs();
  for (int i = 0; i < 16; ++i) pool.Add(tasks[i].get(), start + i * 37'000);
  ASSERT_TRUE(WaitFor([&] {
    for (auto& t : tasks) if (t->ticks_.load() < 50) return false;
    return true;
  }));
  for (auto& t : tasks) pool.Remove(t.get());
  for (auto& t : tasks) EXPECT_EQ(t->early_.load(), 0);
}

TEST_P(TickPoolWaits, WakeBringsAnIdleTaskForward) {
  TickPool pool(1, TickPool::kDefaultCoalesceNs, GetParam());
  PeriodicTask task(0);  // no deadline of its own: ticks only when woken
  pool.Add(&task, kNeverNs);
  std::this_thread::sleep_for(std::chrono::milliseconds(20));
  EXPECT_EQ(task.ticks_.load(), 0);
  const std::int64_t woken_at = SteadyNowNs();
  pool.Wake(&task, woken_at);
  ASSERT_TRUE(WaitFor([&] { return task.ticks_.load() == 1; }));
  EXPECT_EQ(task.last_due_ns_.load(), woken_at);
  pool.Wake(&task, SteadyNowNs());
  ASSERT_TRUE(WaitFor([&] { return task.ticks_.load() == 2; }));
  pool.Remove(&task);
}

TEST_P(TickPoolWaits, AWakeLaterThanThePendingTickChangesNothing) {
  TickPool pool(1, TickPool::kDefaultCoalesceNs, GetParam());
  PeriodicTask task(0);
  const std::int64_t due = SteadyNowNs() + 30 * kMs;
  pool.Add(&task, due);
  pool.Wake(&task, due + 100 * kMs);
  ASSERT_TRUE(WaitFor([&] { return task.ticks_.load() == 1; }));
  EXPECT_EQ(task.last_due_ns_.load(), due);
  std::this_thread::sleep_for(std::chrono::milliseconds(150));
  EXPECT_EQ(task.ticks_.load(), 1);  // the later wake was absorbed, not queued
  pool.Remove(&task);
}

TEST_P(TickPoolWaits, ATaskNeverRunsOnTwoWorkersAtOnceAndAWakeDuringItsTickIsKept) {
  TickPool pool(4, TickPool::kDefaultCoalesceNs, GetParam());
  PeriodicTask task(0, /*work_ns=*/2 * kMs);
  pool.Add(&task, SteadyNowNs());
  // Hammer it with wakes while it runs: each must be kept (as a rerun), none
  // may start a second concurrent tick.
  for (int i = 0; i < 200; ++i) {
    pool.Wake(&task, SteadyNowNs());
    std::this_thread::sleep_for(std::chrono::microseconds(100));
  }
  const int before = task.ticks_.load();
  EXPECT_GE(before, 5);
  pool.Wake(&task, SteadyNowNs());
  ASSERT_TRUE(WaitFor([&] { return task.ticks_.load() > before; }));
  pool.Remove(&task);
  EXPECT_EQ(task.overlaps_.load(), 0);
}

TEST_P(TickPoolWaits, RemoveWaitsForTheRunningTickAndNoTickFollows) {
  TickPool pool(2, TickPool::kDefaultCoalesceNs, GetParam());
  auto task = std::make_unique<PeriodicTask>(kMs, /*work_ns=*/5 * kMs);
  pool.Add(task.get(), SteadyNowNs());
  ASSERT_TRUE(WaitFor([&] { return task->ticks_.load() >= 1; }));
  pool.Remove(task.get());
  const int after_remove = task->ticks_.load();
  pool.Wake(task.get(), SteadyNowNs());  // ignored: no longer registered
  std::this_thread::sleep_for(std::chrono::milliseconds(30));
  EXPECT_EQ(task->ticks_.load(), after_remove);
  task.reset();  // destroying it now must be safe: the heap holds no pointer to it
  std::this_thread::sleep_for(std::chrono::milliseconds(10));
}

TEST_P(TickPoolWaits, SixtyFourTasksAtOneKilohertzAllKeepTicking) {
  TickPool pool(2, TickPool::kDefaultCoalesceNs, GetParam());
  std::vector<std::unique_ptr<PeriodicTask>> tasks;
  const std::int64_t start = SteadyNowNs();
  for (int i = 0; i < 64; ++i) {
    tasks.push_back(std::make_unique<PeriodicTask>(kMs));
    pool.Add(tasks.back().get(), start);
  }
  std::this_thread::sleep_for(std::chrono::milliseconds(300));
  for (auto& t : tasks) pool.Remove(t.get());
  const double elapsed_ms = static_cast<double>(SteadyNowNs() - start) / kMs;
  for (auto& t : tasks) {
    // Each task ticks once per ms of wall time; a shared CI core may steal
    // time, and after a stall a task catches up, so only its progress and
    // its bound are checked: never more ticks than elapsed periods (+1).
    EXPECT_GE(t->ticks_.load(), 100);
    EXPECT_LE(t->ticks_.load(), static_cast<int>(elapsed_ms) + 1);
    EXPECT_EQ(t->overlaps_.load(), 0);
  }
  EXPECT_GE(pool.stats().ticks, 64u * 100u);
}

// This process's CPU time [ns] (the test's thread sleeps: the rest is the pool's).
std::int64_t ProcessCpuNs() {
  timespec t{};
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &t);
  return std::int64_t{t.tv_sec} * 1'000'000'000 + t.tv_nsec;
}

// What the two ways of waiting are for: a spinning worker keeps its CPU busy
// while its next tick is far off (the CPU never idles), a sleeping one leaves
// it idle. On a shared CI core the spinner gets at least a share of it.
TEST(TickPool, ASpinningWorkerKeepsItsCpuBusyBetweenTicksAndASleepingOneDoesNot) {
  for (const common::IdleWait wait : {common::IdleWait::kSleep, common::IdleWait::kSpin}) {
    TickPool pool(1, TickPool::kDefaultCoalesceNs, wait);
    PeriodicTask task(0);
    pool.Add(&task, SteadyNowNs() + 10'000 * kMs);  // nothing due during the measurement
    const std::int64_t wall0 = SteadyNowNs(), cpu0 = ProcessCpuNs();
    std::this_thread::sleep_for(std::chrono::milliseconds(100));
    const double busy = static_cast<double>(ProcessCpuNs() - cpu0) / static_cast<double>(SteadyNowNs() - wall0);
    pool.Remove(&task);
    EXPECT_EQ(task.ticks_.load(), 0);
    if (wait == common::IdleWait::kSpin) {
      EXPECT_GT(busy, 0.25) << "a spinning worker left its CPU idle";
    } else {
      EXPECT_LT(busy, 0.05) << "a sleeping worker kept its CPU busy";
    }
  }
}

INSTANTIATE_TEST_SUITE_P(SleepAndSpin, TickPoolWaits,
                         ::testing::Values(common::IdleWait::kSleep, common::IdleWait::kSpin),
                         [](const ::testing::TestParamInfo<common::IdleWait>& param) {
                           return param.param == common::IdleWait::kSleep ? "Sleep" : "Spin";
                         });

TEST(TickPool, RefusesAnUnusableWorkerCount) {
  EXPECT_THROW(TickPool(0), std::invalid_argument);
  EXPECT_GE(DefaultWorkerCount(), 1);
}

}  // namespace
}  // namespace hapsim::service
