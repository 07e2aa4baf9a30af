// How a thread of ours presents itself to the OS: work that can wait (scene
// builds, the recording and database writers) runs below the 1 kHz tick, so
// the tick preempts it when both want the core; and threads worth telling
// apart in top, perf and /proc/PID/task carry a name.
#pragma once

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

}  // namespace hapsim::common
