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
    const int argc = static_cast<int>(argv.size() - 1);
    const auto r = flags.Parse(argc, argv.data(), &error);
    if (r == hapsim::common::Flags::Result::kError && error.empty()) std::abort();  // an error always says why
    // As hapsim-ctl: global flags up to the command, then the command's own
    // flags (a repeatable one) and its positional ids.
    int command_at = -1;
    error.clear();
    const auto global = flags.Parse(argc, argv.data(), &error, &command_at);
    if (command_at < 1 || command_at > argc) std::abort();
    if (global == hapsim::common::Flags::Result::kOk && command_at < argc) {
      std::vector<std::string> params, ids;
      std::string scene;
      hapsim::common::Flags command("hapsim-fuzz cmd", "a command", "ID [flags]");
      command.Add("scene", &scene, "a scene");
      command.AddList("param", &params, "KEY=NUMBER");
      command.AllowPositionals(&ids);
      error.clear();
      const auto c = command.Parse(argc - command_at, argv.data() + command_at, &error);
      if (c == hapsim::common::Flags::Result::kError && error.empty()) std::abort();
      if (c == hapsim::common::Flags::Result::kOk && ids.size() + params.size() > static_cast<std::size_t>(argc))
        std::abort();
    }
  } catch (...) {
    std::abort();
  }
  return 0;
}
