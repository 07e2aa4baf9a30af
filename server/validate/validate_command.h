// Subcommand registry for hapsim-validate. Each validation lives in its own
// file and registers itself with a static HAPSIM_VALIDATE_COMMAND(...), so
// adding one never touches main.
#pragma once
#include <filesystem>
#include <string>
#include <vector>

namespace hapsim::validate {

struct ValidateCommand {
  std::string name;     // e.g. "integrators"
  std::string summary;  // one line for --help
  // Writes its CSV/markdown into out_dir (created by main). Returns a process
  // exit code: 0 when every reference comparison it makes is within tolerance.
  int (*run)(const std::filesystem::path& out_dir);
};

std::vector<ValidateCommand>& Registry();

struct Registrar {
  explicit Registrar(ValidateCommand command) { Registry().push_back(std::move(command)); }
};

}  // namespace hapsim::validate

#define HAPSIM_VALIDATE_CONCAT2(a, b) a##b
#define HAPSIM_VALIDATE_CONCAT(a, b) HAPSIM_VALIDATE_CONCAT2(a, b)
#define HAPSIM_VALIDATE_COMMAND(name, summary, fn) \
  static const ::hapsim::validate::Registrar HAPSIM_VALIDATE_CONCAT(hapsim_validate_reg_, __LINE__){{name, summary, fn}}
