// One clock for every latency figure: the steady (monotonic) clock in ns;
// and wall-clock times as people read them.
#pragma once
#include <chrono>
#include <cstdint>
#include <ctime>
#include <string>

namespace hapsim::common {

inline std::int64_t SteadyNowNs() {
  return std::chrono::duration_cast<std::chrono::nanoseconds>(
             std::chrono::steady_clock::now().time_since_epoch())
      .count();
}

// A Unix time [ms] in this machine's local time, formatted by strftime
// (e.g. "%Y-%m-%d %H:%M:%S"); "-" for 0 or less (not set).
inline std::string LocalTimeText(std::int64_t unix_ms, const char* strftime_format) {
  if (unix_ms <= 0) return "-";
  const std::time_t t = static_cast<std::time_t>(unix_ms / 1000);
  std::tm local{};
  localtime_r(&t, &local);
  char text[64];
  return std::strftime(text, sizeof text, strftime_format, &local) > 0 ? text : "-";
}

}  // namespace hapsim::common
