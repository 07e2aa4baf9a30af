// Any bytes as a command line (NUL-separated arguments) for a flag set like
// the executables': Flags::Parse answers ok, help or an error with a
// message, and never crashes or throws.
#include <cstdint>
#include <cstdlib>
#include <string>
#include <vector>

#include "hapsim/common/flags.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  std::vector<std::string> args{"hapsim-fuzz"};
  std::string current;
  for (std::size_t i = 0; i < size && args.size() < 64; ++i) {
    if (data[i] == 0) {
      args.push_back(current);
      current.clear();
    } else {
      current.push_back(static_cast<char>(data[i]));
    }
  }
  if (!current.empty()) args.push_back(current);
  std::vector<char*> argv;
  for (auto& a : args) argv.push_back(a.data());
  argv.push_back(nullptr);

  std::string server = "127.0.0.1:50051", name;
  double seconds = 10.0, rate = 1000.0;
  int devices = 1, seed = 1;
  bool verbose = false;
  hapsim::common::Flags flags("hapsim-fuzz", "fuzzed flag set");
  flags.Add("server", &server, "address");
  flags.Add("name", &name, "a name");
  flags.Add("seconds", &seconds, "duration [s]");
  flags.Add("rate-hz", &rate, "rate [Hz]");
  flags.Add("devices", &devices, "count");
  flags.Add("seed", &seed, "seed");
  flags.Add("verbose", &verbose, "switch");
  std::string error;
  try {
    const auto r = flags.Parse(static_cast<int>(argv.size() - 1), argv.data(), &error);
    if (r == hapsim::common::Flags::Result::kError && error.empty()) std::abort();  // an error always says why
  } catch (...) {
    std::abort();
  }
  return 0;
}
