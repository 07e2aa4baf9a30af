// One clock for every latency figure: the steady (monotonic) clock in ns.
#pragma once
#include <chrono>
#include <cstdint>

namespace hapsim::common {

inline std::int64_t SteadyNowNs() {
  return std::chrono::duration_cast<std::chrono::nanoseconds>(
             std::chrono::steady_clock::now().time_since_epoch())
      .count();
}

}  // namespace hapsim::common
