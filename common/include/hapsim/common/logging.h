// spdlog set-up shared by the executables: one named logger per process,
// level from --log-level (trace, debug, info, warn, error, off).
#pragma once
#include <string>

namespace hapsim::common {

// Returns false (and leaves the level unchanged) for an unknown level name.
bool SetUpLogging(const std::string& process_name, const std::string& level);

}  // namespace hapsim::common
