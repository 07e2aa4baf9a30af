#include "hapsim/runtime/scene_builder.h"

#include <exception>
#include <thread>

#include "hapsim/common/thread_setup.h"

namespace hapsim::service {

void RunAtLowPriority(const std::function<void()>& work) {
  std::exception_ptr error;
  std::thread builder([&] {
    common::LowerThisThreadPriority();
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
