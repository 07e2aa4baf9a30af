// Wall-clock times as people read them.
#pragma once
#include <cstdint>
#include <string>

namespace hapsim::common {

// A Unix time [ms] in this machine's local time, formatted by strftime
// (e.g. "%Y-%m-%d %H:%M:%S"); "-" for 0 or less (not set).
std::string LocalTimeText(std::int64_t unix_ms, const char* strftime_format);

}  // namespace hapsim::common
