#include "hapsim/runtime/tick_pool.h"

#include <sched.h>
#include <sys/prctl.h>

#include <algorithm>
#include <chrono>
#include <stdexcept>

#include "hapsim/common/clock.h"
#include "hapsim/common/thread_setup.h"

namespace hapsim::service {

namespace {

// Min-heap order on due time.
bool LaterThan(const auto& a, const auto& b) { return a.due_ns > b.due_ns; }

std::chrono::steady_clock::time_point AtSteadyNs(std::int64_t ns) {
  return std::chrono::steady_clock::time_point(std::chrono::nanoseconds(ns));
}

}  // namespace

int DefaultWorkerCount() {
  cpu_set_t set;
  CPU_ZERO(&set);
  if (sched_getaffinity(0, sizeof set, &set) != 0) return 1;
  return std::max(1, CPU_COUNT(&set));
}

TickPool::TickPool(int workers, std::int64_t coalesce_ns, common::IdleWait wait)
    : coalesce_ns_(coalesce_ns), wait_(wait) {
  if (workers < 1 || workers > 256) throw std::invalid_argument("tick pool: workers must be within [1, 256]");
  heap_.reserve(1024);
  threads_.reserve(static_cast<std::size_t>(workers));
  for (int i = 0; i < workers; ++i) {
    threads_.emplace_back([this] { WorkerLoop(); });
    common::NameThread(threads_.back(), kWorkerThreadName);  // found by name for real-time priority
  }
}

TickPool::~TickPool() { Stop(); }

void TickPool::Stop() {
  {
    std::lock_guard lock(mutex_);
    if (stop_) return;
    stop_ = true;
  }
  NotifyAll();
  for (auto& t : threads_) t.join();
}

TickPoolStats TickPool::stats() const {
  std::lock_guard lock(mutex_);
  return stats_;
}

bool TickPool::IsStaleLocked(const Entry& e) const {
  return !e.task->registered_ || e.generation != e.task->generation_;
}

void TickPool::PushLocked(TickTask* task, std::int64_t due_ns) {
  ++task->generation_;
  task->queued_due_ns_ = due_ns;
  heap_.push_back({due_ns, task->generation_, task});
  std::push_heap(heap_.begin(), heap_.end(), [](const Entry& a, const Entry& b) { return LaterThan(a, b); });
}

void TickPool::Add(TickTask* task, std::int64_t first_due_ns) {
  {
    std::lock_guard lock(mutex_);
    if (task->registered_) return;
    task->registered_ = true;
    task->running_ = false;
    task->rerun_due_ns_ = kNeverNs;
    PushLocked(task, first_due_ns);
  }
  NotifyOne();
}

void TickPool::Remove(TickTask* task) {
  std::unique_lock lock(mutex_);
  if (!task->registered_) return;
  task->registered_ = false;
  // Purge its entries now: the heap holds raw pointers, and the task may be
  // destroyed as soon as this returns.
  std::erase_if(heap_, [task](const Entry& e) { return e.task == task; });
  std::make_heap(heap_.begin(), heap_.end(), [](const Entry& a, const Entry& b) { return LaterThan(a, b); });
  task->queued_due_ns_ = kNeverNs;
  removed_cv_.wait(lock, [task] { return !task->running_; });
}

void TickPool::Wake(TickTask* task, std::int64_t due_ns) {
  {
    std::lock_guard lock(mutex_);
    if (!task->registered_) return;
    if (task->running_) {
      task->rerun_due_ns_ = std::min(task->rerun_due_ns_, due_ns);
      return;
    }
    if (due_ns >= task->queued_due_ns_) return;
    PushLocked(task, due_ns);
    if (heap_.front().task != task) return;  // an earlier tick is already pending: nobody needs waking
  }
  NotifyOne();
}

// Sleeping workers wait on the condition variable alone: the counter (an
// atomic add on every pose's wake-up) is kept only for spinning ones.
void TickPool::NotifyOne() {
  if (wait_ == common::IdleWait::kSpin) posted_.fetch_add(1, std::memory_order_release);
  work_cv_.notify_one();
}

void TickPool::NotifyAll() {
  if (wait_ == common::IdleWait::kSpin) posted_.fetch_add(1, std::memory_order_release);
  work_cv_.notify_all();
}

void TickPool::WorkerLoop() {
  // Wake on time: the default timer slack (50 µs) is 5 % of a 1 kHz period.
  prctl(PR_SET_TIMERSLACK, 1UL, 0UL, 0UL, 0UL);
  std::unique_lock lock(mutex_);
  while (!stop_) {
    DropStaleLocked();
    if (heap_.empty()) {
      WaitForWork(lock, kNeverNs);
      ++stats_.wakeups;
      continue;
    }
    const std::int64_t now_ns = common::SteadyNowNs();
    const Entry top = heap_.front();
    if (top.due_ns > now_ns + coalesce_ns_) {
      WaitForWork(lock, top.due_ns);
      ++stats_.wakeups;
      continue;
    }
    RunTopTick(lock, now_ns);
  }
}

void TickPool::WaitForWork(std::unique_lock<std::mutex>& lock, std::int64_t until_ns) {
  if (wait_ == common::IdleWait::kSleep) {
    if (until_ns == kNeverNs) {
      work_cv_.wait(lock);
    } else {
      work_cv_.wait_until(lock, AtSteadyNs(until_ns));
    }
    return;
  }
  // Read under the lock: work posted after the unlock changes it.
  const std::uint64_t seen = posted_.load(std::memory_order_acquire);
  lock.unlock();
  while (posted_.load(std::memory_order_acquire) == seen && common::SteadyNowNs() < until_ns) sched_yield();
  lock.lock();
}

void TickPool::PopTopLocked() {
  std::pop_heap(heap_.begin(), heap_.end(), [](const Entry& a, const Entry& b) { return LaterThan(a, b); });
  heap_.pop_back();
}

void TickPool::DropStaleLocked() {
  while (!heap_.empty() && IsStaleLocked(heap_.front())) PopTopLocked();
}

void TickPool::RunTopTick(std::unique_lock<std::mutex>& lock, std::int64_t now_ns) {
  const Entry top = heap_.front();
  PopTopLocked();
  TickTask* task = top.task;
  task->running_ = true;
  task->queued_due_ns_ = kNeverNs;
  // More ticks due now: recruit an idle worker for them.
  const bool more_due = !heap_.empty() && heap_.front().due_ns <= now_ns + coalesce_ns_;
  lock.unlock();
  if (more_due) NotifyOne();
  const std::int64_t next_due_ns = task->RunTick(top.due_ns, common::SteadyNowNs());
  lock.lock();
  ++stats_.ticks;
  task->running_ = false;
  if (!task->registered_) {
    removed_cv_.notify_all();
    return;
  }
  const std::int64_t due_ns = std::min(next_due_ns, task->rerun_due_ns_);
  task->rerun_due_ns_ = kNeverNs;
  if (due_ns != kNeverNs) PushLocked(task, due_ns);  // this worker loops and sees it: no notify
}

}  // namespace hapsim::service
