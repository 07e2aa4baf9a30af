// How a thread of ours presents itself to the OS: work that can wait (scene
// builds, the recording and database writers) runs below the 1 kHz tick, so
// the tick preempts it when both want the core; and threads worth telling
// apart in top, perf and /proc/PID/task carry a name.
#pragma once
#include <initializer_list>
#include <thread>

namespace hapsim::common {

// Nice 10: a tenth of a busy tick thread's CPU share (weight 110 vs 1024),
// so due ticks preempt the work, yet it still progresses on a saturated
// machine (at nice 19, weight 15, a scene build starved for tens of seconds).
inline constexpr int kBackgroundNice = 10;

// Lowers the calling thread (Linux: nice is per thread). A refusal only
// costs priority, never correctness, so it is ignored.
void LowerThisThreadPriority(int nice = kBackgroundNice);

// SCHED_IDLE: the thread runs only when no normal thread wants the core,
// and a waking tick preempts it at once (nice alone lets a background burst
// run on for a scheduler slice). For work with its own buffer (the recording
// writer's 4 s queue); under a saturated core it starves, and what it drops
// is counted. Falls back to LowerThisThreadPriority() if refused.
void RunThisThreadOnlyWhenIdle();

// At most 15 characters (the kernel's limit; longer names are cut).
void NameThisThread(const char* name);
// The same for a thread this one started (named before it returns, so a
// RaiseThreadsNamed right after finds it).
void NameThread(std::thread& thread, const char* name);

// Real-time priority for the threads of the 1 kHz path (tick workers, the
// receive threads that carry poses): SCHED_FIFO at `priority` (1..99) for
// every thread of this process whose name is one of `names`, so a due tick
// preempts viewer streaming, gRPC, metrics and recording on a shared core.
// Needs CAP_SYS_NICE or an RLIMIT_RTPRIO of at least `priority`; where
// refused the threads keep their normal priority (reported, never fatal).
// The kernel's RT throttling (sched_rt_runtime_us, 95 % by default) still
// leaves the rest of the machine a share if these threads ever spin.
struct RealtimeResult {
  int raised = 0;   // threads now at SCHED_FIFO `priority`
  int refused = 0;  // threads found by name whose change the kernel refused
};
RealtimeResult RaiseThreadsNamed(std::initializer_list<const char*> names, int priority);
// The calling thread at SCHED_FIFO `priority`; false where refused (unchanged).
bool RunThisThreadAtRealtime(int priority);

}  // namespace hapsim::common
