// Shared start-up of the service fuzz targets: silence the log (thousands of
// inputs would drown the fuzzer's own output) and, with
// HAPSIM_FUZZ_WRITE_SEEDS=DIR, write the target's seed inputs there and exit
// (how tests/fuzz/corpus/<name>/ is made from real messages).
#pragma once
#include <cstdlib>
#include <string>

#include <spdlog/spdlog.h>

namespace hapsim::fuzz {

inline void SetUpServiceFuzzer(void (*write_seeds)(const std::string& dir)) {
  spdlog::set_level(spdlog::level::off);
  if (const char* dir = std::getenv("HAPSIM_FUZZ_WRITE_SEEDS")) {
    write_seeds(dir);
    std::exit(0);
  }
}

}  // namespace hapsim::fuzz
