#include "hapsim/service/scene_builder.h"

#include <sys/resource.h>
#include <unistd.h>

#include <exception>
#include <thread>

namespace hapsim::service {

std::unique_ptr<core::Scene> BuildSceneAtLowPriority(const core::SceneSpec& spec) {
  std::unique_ptr<core::Scene> scene;
  std::exception_ptr error;
  std::thread builder([&] {
    // Per-thread nice on Linux; failure only costs priority, not correctness.
    (void)setpriority(PRIO_PROCESS, static_cast<id_t>(gettid()), 19);
    try {
      scene = core::MakeScene(spec);
    } catch (...) {
      error = std::current_exception();
    }
  });
  builder.join();
  if (error) std::rethrow_exception(error);
  return scene;
}

}  // namespace hapsim::service
