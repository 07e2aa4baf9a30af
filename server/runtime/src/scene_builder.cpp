#include "hapsim/runtime/scene_builder.h"

#include <sys/resource.h>
#include <unistd.h>

#include <exception>
#include <thread>

namespace hapsim::service {

// Nice 10: a tenth of a busy tick thread's CPU share (weight 110 vs 1024),
// so due ticks preempt the build, yet a build still finishes on a saturated
// machine (at nice 19, weight 15, it starved for tens of seconds).
constexpr int kBuildNice = 10;

void RunAtLowPriority(const std::function<void()>& work) {
  std::exception_ptr error;
  std::thread builder([&] {
    // Per-thread nice on Linux; failure only costs priority, not correctness.
    (void)setpriority(PRIO_PROCESS, static_cast<id_t>(gettid()), kBuildNice);
    try {
      work();
    } catch (...) {
      error = std::current_exception();
    }
  });
  builder.join();
  if (error) std::rethrow_exception(error);
}

}  // namespace hapsim::service
