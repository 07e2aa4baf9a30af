#include "hapsim/common/flags.h"

#include <cmath>
#include <cstdlib>
#include <sstream>

namespace hapsim::common {

namespace {
std::string FormatDouble(double v) {
  std::ostringstream s;
  s << v;
  return s.str();
}
}  // namespace

Flags::Flags(std::string program, std::string summary, std::string synopsis)
    : program_(std::move(program)), summary_(std::move(summary)), synopsis_(std::move(synopsis)) {}

void Flags::Add(const std::string& name, std::string* value, const std::string& help) {
  flags_.push_back({name, help, value->empty() ? "\"\"" : *value, false,
                    [value](const std::string& s) { *value = s; return true; }});
}

void Flags::Add(const std::string& name, double* value, const std::string& help) {
  flags_.push_back({name, help, FormatDouble(*value), false, [value](const std::string& s) {
                      char* end = nullptr;
                      const double v = std::strtod(s.c_str(), &end);
                      if (s.empty() || *end != '\0' || !std::isfinite(v)) return false;
                      *value = v;
                      return true;
                    }});
}

void Flags::Add(const std::string& name, int* value, const std::string& help) {
  flags_.push_back({name, help, std::to_string(*value), false, [value](const std::string& s) {
                      char* end = nullptr;
                      const long v = std::strtol(s.c_str(), &end, 10);
                      if (s.empty() || *end != '\0' || v < -2147483647L || v > 2147483647L) return false;
                      *value = static_cast<int>(v);
                      return true;
                    }});
}

void Flags::Add(const std::string& name, bool* value, const std::string& help) {
  flags_.push_back({name, help, *value ? "on" : "off", true, [value](const std::string& s) {
                      if (s.empty() || s == "true" || s == "1") { *value = true; return true; }
                      if (s == "false" || s == "0") { *value = false; return true; }
                      return false;
                    }});
}

void Flags::AddList(const std::string& name, std::vector<std::string>* values, const std::string& help) {
  flags_.push_back({name, help + "; may be repeated", "none", false, [values](const std::string& s) {
                      values->push_back(s);
                      return true;
                    }});
}

std::string VersionLine(const std::string& program) { return program + " " + HAPSIM_VERSION + "\n"; }

Flags::Result Flags::Parse(int argc, char** argv, std::string* error, int* command_at) {
  if (command_at) *command_at = argc;
  for (int i = 1; i < argc; ++i) {
    std::string arg = argv[i];
    if (arg == "--help" || arg == "-h") return Result::kHelp;
    if (arg == "--version") return Result::kVersion;
    if (arg.rfind("--", 0) != 0) {  // not a flag: the command, a positional, or a mistake
      if (command_at) {
        *command_at = i;
        return Result::kOk;
      }
      if (!positionals_) {
        *error = "unexpected argument '" + arg + "' (flags start with --; see --help)";
        return Result::kError;
      }
      positionals_->push_back(arg);
      continue;
    }
    if (!ParseFlag(arg, argc, argv, &i, error)) return Result::kError;
  }
  return Result::kOk;
}

Flags::Flag* Flags::FindFlag(const std::string& name) {
  Flag* flag = nullptr;
  for (auto& f : flags_) {
    if (f.name == name) flag = &f;  // the last one declared wins
  }
  return flag;
}

bool Flags::ParseFlag(const std::string& arg, int argc, char** argv, int* i, std::string* error) {
  std::string name = arg.substr(2), value;
  bool has_value = false;
  if (const auto eq = name.find('='); eq != std::string::npos) {
    value = name.substr(eq + 1);
    name = name.substr(0, eq);
    has_value = true;
  }
  Flag* flag = FindFlag(name);
  if (!flag) {
    *error = "unknown flag --" + name + " (see --help)";
    return false;
  }
  if (!has_value && !flag->is_switch) {
    if (*i + 1 >= argc) {
      *error = "flag --" + name + " needs a value (see --help)";
      return false;
    }
    value = argv[++*i];
  }
  if (!flag->set(value)) {
    *error = "bad value '" + value + "' for --" + name + " (see --help)";
    return false;
  }
  return true;
}

std::string FirstFlagOutOfRange(std::initializer_list<FlagRange> ranges) {
  for (const auto& r : ranges) {
    if (!r.ok) return std::string(r.flag) + " must be within " + r.range + " (see --help)";
  }
  return "";
}

std::string Flags::Help() const {
  std::ostringstream out;
  out << "usage: " << program_ << " " << synopsis_ << "\n\n" << summary_ << "\n\nflags:\n";
  for (const auto& f : flags_) {
    std::string lhs = "  --" + f.name + (f.is_switch ? "" : " VALUE");
    out << lhs;
    if (lhs.size() < 30) out << std::string(30 - lhs.size(), ' ');
    else out << "\n" << std::string(30, ' ');
    out << f.help << " (default: " << f.default_text << ")\n";
  }
  out << "  --help                      show this help and exit\n";
  return out.str();
}

}  // namespace hapsim::common
