// hapsim-validate: run a validation and write its tables.
//   hapsim-validate <command> --out DIR
#include <algorithm>
#include <cstdio>
#include <cstring>
#include <exception>
#include <string>

#include "validate_command.h"

namespace hapsim::validate {
std::vector<ValidateCommand>& Registry() {
  static std::vector<ValidateCommand> commands;
  return commands;
}
}  // namespace hapsim::validate

namespace {

void PrintHelp() {
  std::printf(
      "usage: hapsim-validate <command> --out DIR\n\n"
      "Runs a numerical validation of hapsim's models against analytic or\n"
      "independent references and writes CSV tables plus a markdown summary\n"
      "into DIR (created if missing). Exits 1 if a checked claim fails.\n\ncommands:\n");
  auto commands = hapsim::validate::Registry();
  std::sort(commands.begin(), commands.end(),
            [](const auto& a, const auto& b) { return a.name < b.name; });
  for (const auto& c : commands) std::printf("  %-14s %s\n", c.name.c_str(), c.summary.c_str());
}

}  // namespace

int main(int argc, char** argv) {
  if (argc == 2 && !std::strcmp(argv[1], "--version")) {
    std::printf("hapsim-validate %s\n", HAPSIM_VERSION);
    return 0;
  }
  if (argc < 2 || !std::strcmp(argv[1], "--help") || !std::strcmp(argv[1], "-h")) {
    PrintHelp();
    return argc < 2 ? 2 : 0;
  }
  const std::string name = argv[1];
  std::string out_dir;
  for (int i = 2; i < argc; ++i) {
    if (!std::strcmp(argv[i], "--out") && i + 1 < argc) {
      out_dir = argv[++i];
    } else if (!std::strcmp(argv[i], "--help") || !std::strcmp(argv[i], "-h")) {
      PrintHelp();
      return 0;
    } else {
      std::fprintf(stderr, "hapsim-validate: unknown argument '%s' (see --help)\n", argv[i]);
      return 2;
    }
  }
  if (out_dir.empty()) {
    std::fprintf(stderr, "hapsim-validate: --out DIR is required (see --help)\n");
    return 2;
  }
  for (const auto& c : hapsim::validate::Registry()) {
    if (c.name != name) continue;
    try {
      std::filesystem::create_directories(out_dir);
      return c.run(out_dir);
    } catch (const std::exception& e) {
      std::fprintf(stderr, "hapsim-validate %s: %s\n", name.c_str(), e.what());
      return 1;
    }
  }
  std::fprintf(stderr, "hapsim-validate: unknown command '%s' (see --help)\n", name.c_str());
  return 2;
}
