// How a 1 kHz thread waits for its next deadline: asleep, or spinning —
// polling the clock (and whatever else wakes it) and yielding its CPU to any
// other runnable thread between polls, so that CPU never idles. On a virtual
// machine an idle CPU may halt and be woken late by the hypervisor, at times
// by milliseconds; a spinning thread's CPU never halts. Spinning costs that
// CPU whole: for CPUs given to the 1 kHz path (docs/performance.md, "A tick
// worker that never sleeps").
#pragma once
#include <optional>
#include <string_view>

namespace hapsim::common {

enum class IdleWait {
  kSleep,  // block until the deadline
  kSpin,   // poll, yielding between polls
};

// "sleep" or "spin"; nullopt for anything else.
std::optional<IdleWait> ParseIdleWait(std::string_view name);
const char* IdleWaitName(IdleWait wait);

}  // namespace hapsim::common
