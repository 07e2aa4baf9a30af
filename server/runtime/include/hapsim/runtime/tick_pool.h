// TickPool: a small pool of worker threads that runs session ticks by
// deadline. Each task (a session) has at most one pending tick, due at an
// absolute time on the steady clock; workers take the earliest due tick,
// run it, and re-queue the task at the deadline its tick returns. Wake()
// brings a pending tick forward — that is how a device's pose clocks its
// session: the DDS thread wakes the session "now" instead of letting it wait
// for its timer.
//
// This is deadline scheduling, not work stealing: one mutex-guarded min-heap
// of (due, task), held only for O(log n) pushes and pops, never while a tick
// runs. A task never runs on two workers at once; a Wake() that arrives while
// its tick runs is remembered and applied when the tick returns. Ticks due
// within `coalesce_ns` of each other run back to back on one wake-up, so many
// sessions on a shared timer grid cost one wake-up per period, not one each.
//
// An idle worker waits for its next tick asleep on a condition variable
// (IdleWait::kSleep, the default) or spinning: polling the clock and the
// posted work, yielding its CPU between polls (common/idle_wait.h: why).
#pragma once
#include <atomic>
#include <condition_variable>
#include <cstdint>
#include <limits>
#include <mutex>
#include <thread>
#include <vector>

#include "hapsim/common/idle_wait.h"

namespace hapsim::service {

inline constexpr std::int64_t kNeverNs = std::numeric_limits<std::int64_t>::max();

// Work the pool runs; subclass and implement RunTick.
class TickTask {
 public:
  virtual ~TickTask() = default;
  // Runs one tick that was due at due_ns (steady clock), on a pool worker;
  // now_ns is when the worker took it. Returns when the next tick is due
  // (kNeverNs: only when woken).
  virtual std::int64_t RunTick(std::int64_t due_ns, std::int64_t now_ns) = 0;

 private:
  friend class TickPool;
  // Scheduler bookkeeping, guarded by the pool's mutex.
  std::int64_t queued_due_ns_ = kNeverNs;  // due time of the valid heap entry
  std::int64_t rerun_due_ns_ = kNeverNs;   // earliest Wake() seen while running
  std::uint64_t generation_ = 0;           // heap entries of older generations are stale
  bool running_ = false;
  bool registered_ = false;
};

struct TickPoolStats {
  std::uint64_t ticks = 0;        // RunTick calls
  std::uint64_t wakeups = 0;      // worker wake-ups (timer or notify; spinning: ends of a wait)
};

class TickPool {
 public:
  static constexpr std::int64_t kDefaultCoalesceNs = 20'000;
  // workers >= 1. Worker threads start at once.
  explicit TickPool(int workers, std::int64_t coalesce_ns = kDefaultCoalesceNs,
                    common::IdleWait wait = common::IdleWait::kSleep);
  static constexpr const char* kWorkerThreadName = "tick-worker";
  ~TickPool();  // Stop()
  TickPool(const TickPool&) = delete;
  TickPool& operator=(const TickPool&) = delete;

  // Starts scheduling task; its first tick is due at first_due_ns. The task
  // must stay alive until Remove(task) has returned.
  void Add(TickTask* task, std::int64_t first_due_ns);
  // Stops scheduling task; waits until a tick of it that is running ends.
  // Afterwards RunTick is never called again and Wake() on it is a no-op.
  // Must not be called from inside that task's RunTick.
  void Remove(TickTask* task);
  // Brings the task's next tick forward to due_ns (no-op if it is already
  // due earlier, or the task is not registered). Thread-safe, cheap.
  void Wake(TickTask* task, std::int64_t due_ns);
  // Ends the worker threads (pending ticks are dropped). Idempotent.
  void Stop();

  int workers() const { return static_cast<int>(threads_.size()); }
  TickPoolStats stats() const;

 private:
  struct Entry {
    std::int64_t due_ns;
    std::uint64_t generation;
    TickTask* task;
  };
  void WorkerLoop();
  // Until until_ns (kNeverNs: no deadline) or until work is posted: the lock
  // is held on entry and on return.
  void WaitForWork(std::unique_lock<std::mutex>& lock, std::int64_t until_ns);
  // Every change a waiting worker must see (a tick pushed earlier, Stop).
  void NotifyOne();
  void NotifyAll();
  // WorkerLoop's steps, under the mutex: drop the heap's stale entries; run
  // the due tick at the top (the lock released while it runs) and reschedule it.
  void DropStaleLocked();
  void RunTopTick(std::unique_lock<std::mutex>& lock, std::int64_t now_ns);
  void PopTopLocked();
  void PushLocked(TickTask* task, std::int64_t due_ns);
  bool IsStaleLocked(const Entry& e) const;

  const std::int64_t coalesce_ns_;
  const common::IdleWait wait_;
  // Spinning workers only: bumped by every notification, polled without the lock.
  std::atomic<std::uint64_t> posted_{0};
  mutable std::mutex mutex_;
  std::condition_variable work_cv_;     // workers wait here
  std::condition_variable removed_cv_;  // Remove() waits here for a running tick
  std::vector<Entry> heap_;             // min-heap on due_ns
  bool stop_ = false;
  TickPoolStats stats_;
  std::vector<std::thread> threads_;
};

// Workers to use by default: the CPUs this process may run on (its affinity
// mask, so `taskset -c 0 hapsim-server` gives 1), at least 1.
int DefaultWorkerCount();

}  // namespace hapsim::service
