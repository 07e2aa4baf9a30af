// Builds a session off the real-time path: on a short-lived thread at low
// CPU priority (nice 10), so that while a large scene is built — and the
// session's snapshot buffers, sized for its mesh, are first touched (thousands
// of page faults for a big scene) — the tick workers on the same core still
// run when they are due (the kernel preempts the builder for them). The
// caller waits for the result.
#pragma once
#include <functional>

namespace hapsim::service {

// Runs work on a nice-10 thread and waits; rethrows what work throws.
void RunAtLowPriority(const std::function<void()>& work);

}  // namespace hapsim::service
