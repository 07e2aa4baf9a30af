// Minimal command-line flags: --name value / --name=value / --bool-flag.
// Every executable declares its flags with help text, so --help always
// documents every flag with its default.
#pragma once
#include <cstdint>
#include <functional>
#include <string>
#include <vector>

namespace hapsim::common {

class Flags {
 public:
  Flags(std::string program, std::string summary);

  void Add(const std::string& name, std::string* value, const std::string& help);
  void Add(const std::string& name, double* value, const std::string& help);
  void Add(const std::string& name, int* value, const std::string& help);
  void Add(const std::string& name, bool* value, const std::string& help);  // switch

  enum class Result { kOk, kHelp, kError };
  // On kHelp the caller prints Help() and exits 0; on kError, *error says what
  // was wrong and the caller exits 2.
  Result Parse(int argc, char** argv, std::string* error);
  std::string Help() const;

 private:
  struct Flag {
    std::string name, help, default_text;
    bool is_switch = false;
    std::function<bool(const std::string&)> set;  // false: not a valid value
  };
  std::string program_, summary_;
  std::vector<Flag> flags_;
};

}  // namespace hapsim::common
