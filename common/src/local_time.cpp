#include "hapsim/common/local_time.h"

#include <ctime>

namespace hapsim::common {

std::string LocalTimeText(std::int64_t unix_ms, const char* strftime_format) {
  if (unix_ms <= 0) return "-";
  const std::time_t t = static_cast<std::time_t>(unix_ms / 1000);
  std::tm local{};
  localtime_r(&t, &local);
  char text[64];
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wformat-nonliteral"  // the callers' formats are literals
  const std::size_t n = std::strftime(text, sizeof text, strftime_format, &local);
#pragma GCC diagnostic pop
  return n > 0 ? std::string(text, n) : "-";
}

}  // namespace hapsim::common
