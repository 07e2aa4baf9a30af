// Reading a TOML config file strictly, for the class config and the server
// directory: errors name the file and the node's line:column, unknown keys
// are errors (a typo is never a silent default), strings are bounded.
// `Error` is the config's own exception type (constructible from a string).
#pragma once
#include <toml++/toml.h>

#include <algorithm>
#include <fstream>
#include <initializer_list>
#include <sstream>
#include <string>
#include <string_view>

namespace hapsim::service {

template <class Error>
class TomlChecker {
 public:
  explicit TomlChecker(std::string_view origin) : origin_(origin) {}

  [[noreturn]] void Fail(const toml::node& where, const std::string& what) const {
    const auto& at = where.source().begin;
    throw Error(origin_ + ":" + std::to_string(at.line) + ":" + std::to_string(at.column) + ": " + what);
  }
  [[noreturn]] void Fail(const std::string& what) const { throw Error(origin_ + ": " + what); }

  void OnlyKeys(const toml::table& table, std::initializer_list<std::string_view> allowed, const char* what) const {
    for (const auto& [key, node] : table) {
      if (std::find(allowed.begin(), allowed.end(), key.str()) == allowed.end()) {
        std::string list;
        for (const auto a : allowed) list += (list.empty() ? "" : ", ") + std::string(a);
        Fail(node, "unknown key '" + std::string(key.str()) + "' in " + what + " (known: " + list + ")");
      }
    }
  }
  std::string String(const toml::table& table, std::string_view key, const char* what, bool required,
                     std::string fallback = "") const {
    const toml::node* node = table.get(key);
    if (!node) {
      if (required) Fail(table, what + std::string(" needs '") + std::string(key) + "'");
      return fallback;
    }
    const auto* s = node->as_string();
    if (!s) Fail(*node, "'" + std::string(key) + "' must be a string");
    if (s->get().size() > 256) Fail(*node, "'" + std::string(key) + "' is longer than 256 characters");
    return s->get();
  }
  const toml::array* Array(const toml::table& table, std::string_view key) const {
    const toml::node* node = table.get(key);
    if (!node) return nullptr;
    const auto* a = node->as_array();
    if (!a) Fail(*node, "'" + std::string(key) + "' must be an array");
    return a;
  }

  toml::table Parse(std::string_view text) const {
    try {
      return toml::parse(text, origin_);
    } catch (const toml::parse_error& e) {
      const auto& at = e.source().begin;
      throw Error(origin_ + ":" + std::to_string(at.line) + ":" + std::to_string(at.column) + ": " +
                  std::string(e.description()));
    }
  }

 private:
  std::string origin_;
};

// A config file's text; throws Error if it cannot be read or is over 1 MiB
// (`what` names the kind of file in the message).
template <class Error>
std::string ReadConfigFile(const std::string& path, const char* what) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw Error(path + ": cannot read the " + what);
  std::ostringstream text;
  text << in.rdbuf();
  if (text.str().size() > (1u << 20)) throw Error(path + ": larger than 1 MiB; not a " + what);
  return text.str();
}

}  // namespace hapsim::service
