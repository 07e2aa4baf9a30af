// Minimal command-line flags: --name value / --name=value / --bool-flag.
// Every executable declares its flags with help text, so --help always
// documents every flag with its default. A tool with commands (hapsim-ctl)
// parses its global flags up to the command, then the command's own flags
// with a second Flags over the rest: one grammar and one set of messages.
#pragma once
#include <cstdint>
#include <functional>
#include <initializer_list>
#include <string>
#include <vector>

namespace hapsim::common {

// "PROGRAM VERSION\n", the project's version (CMake's project() VERSION).
std::string VersionLine(const std::string& program);

class Flags {
 public:
  // synopsis: what follows the program name in the usage line.
  Flags(std::string program, std::string summary, std::string synopsis = "[flags]");

  void Add(const std::string& name, std::string* value, const std::string& help);
  void Add(const std::string& name, double* value, const std::string& help);
  void Add(const std::string& name, int* value, const std::string& help);
  void Add(const std::string& name, bool* value, const std::string& help);  // switch
  // A flag that may be given many times; each value is appended.
  void AddList(const std::string& name, std::vector<std::string>* values, const std::string& help);
  // Arguments that are not flags are appended to *out instead of being an
  // error (e.g. a command's session id).
  void AllowPositionals(std::vector<std::string>* out) { positionals_ = out; }

  enum class Result { kOk, kHelp, kVersion, kError };
  // On kHelp the caller prints Help() and exits 0, on kVersion Version(); on
  // kError, *error says what was wrong and the caller exits 2.
  // With command_at, parsing stops at the first argument that is not a flag
  // and *command_at is its index (argc if there is none).
  Result Parse(int argc, char** argv, std::string* error, int* command_at = nullptr);
  std::string Help() const;
  std::string Version() const { return VersionLine(program_); }

 private:
  struct Flag {
    std::string name, help, default_text;
    bool is_switch = false;
    std::function<bool(const std::string&)> set;  // false: not a valid value
  };
  Flag* FindFlag(const std::string& name);  // nullptr: no such flag
  // One "--name", "--name=value" or "--name value" at argv[*i] (arg); a
  // separate value advances *i. False with *error set on a bad flag or value.
  bool ParseFlag(const std::string& arg, int argc, char** argv, int* i, std::string* error);
  std::string program_, summary_, synopsis_;
  std::vector<Flag> flags_;
  std::vector<std::string>* positionals_ = nullptr;
};

// One flag's range check: ok is the check's result, range is what --help
// users read ("(0, 1000]").
struct FlagRange {
  bool ok;
  const char* flag;
  const char* range;
};
// The first failed check as "--flag must be within RANGE (see --help)", or ""
// if all hold. Every executable exits 2 with it, so a bad value is named at
// start, never surfacing later as someone else's error.
std::string FirstFlagOutOfRange(std::initializer_list<FlagRange> ranges);

// Bounds for durations given as flags [s]: long enough for any real run,
// short enough that converting to nanoseconds or to tick counts cannot
// overflow (1e7 s is ~116 days; 1e7 s x 1e9 ns/s fits int64 a thousand times).
inline constexpr double kMaxFlagSeconds = 1e7;
inline constexpr const char* kMaxFlagSecondsRange = "[0, 1e7]";

}  // namespace hapsim::common
