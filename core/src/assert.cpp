// The core's only output: a failed programming-error check, right before
// abort() (assert.h). Allowed <cstdio> by cmake/HapsimLayers.cmake.
#include "hapsim/core/assert.h"

#include <cstdio>
#include <cstdlib>

namespace hapsim::core {

void AbortOnFailedCheck(const char* kind, const char* condition, const char* file, int line,
                        const char* message) noexcept {
  std::fprintf(stderr, "hapsim: %s:%d: %s failed: %s: %s\n", file, line, kind, condition, message);
  std::fflush(stderr);
  std::abort();
}

}  // namespace hapsim::core
