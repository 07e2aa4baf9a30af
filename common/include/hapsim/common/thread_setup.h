// How a thread of ours presents itself to the OS: work that can wait (scene
// builds, the recording and database writers) runs below the 1 kHz tick, so
// the tick preempts it when both want the core; and threads worth telling
// apart in top, perf and /proc/PID/task carry a name.
#pragma once
#include <functional>
#include <initializer_list>
#include <optional>
#include <string>
#include <thread>
#include <vector>

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

// SCHED_BATCH: the thread's share of the core is unchanged, but waking it
// does not preempt the thread that woke it — it runs once that one blocks
// or its slice ends. For a thread another wakes while holding a lock it
// then needs (Cyclone's receive thread signals a waitset under its mutex):
// preempting there only to block on that mutex costs two extra context
// switches per wake. Refusal is ignored (it changes speed, not results).
void RunThreadInBatch(std::thread& thread);  // a thread this one started (in effect when it returns)

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
// The same for the threads for which chosen(their name) is true.
RealtimeResult RaiseThreadsWhere(const std::function<bool(const std::string& name)>& chosen, int priority);

// A core of its own for the 1 kHz path: the threads for which on_tick_path
// (their name) is true run only on `tick_cpus`, every other thread of this
// process only on the CPUs it may use besides them — and so does any thread
// started later by one of those (a new thread inherits its creator's CPUs),
// so viewer streaming, gRPC, the web console and recording never share a
// core with a tick. Complements real-time priority: that decides who runs
// first on a shared core, this keeps the cores apart (and with them the
// kernel's work for those threads' sockets, done on their own cores).
struct AffinityResult {
  int tick_path = 0;  // threads now on tick_cpus only
  int others = 0;     // threads now on the other CPUs only
  int refused = 0;    // threads whose change the kernel refused
};
// "" if `tick_cpus` can be used, else why not: a CPU this process may not
// run on, none given, or none left for the other threads.
std::string CheckTickCpus(const std::vector<int>& tick_cpus);
// Call CheckTickCpus first. Reads the process's CPUs from the calling thread.
AffinityResult SplitThreadsByCpu(const std::function<bool(const std::string& name)>& on_tick_path,
                                 const std::vector<int>& tick_cpus);
// The CPUs of this thread (sched_getaffinity), ascending.
std::vector<int> CpusOfThread(int tid);

// "0", "0,2", "2-3,6": CPU numbers, ascending and distinct; nullopt if the
// text is not such a list.
std::optional<std::vector<int>> ParseCpuList(const std::string& text);
// The calling thread at SCHED_FIFO `priority`; false where refused (unchanged).
bool RunThisThreadAtRealtime(int priority);

}  // namespace hapsim::common
