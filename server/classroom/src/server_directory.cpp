#include "hapsim/classroom/server_directory.h"

#include <algorithm>
#include <set>

#include "toml_checker.h"

namespace hapsim::service {

namespace {

using Checker = TomlChecker<ClassConfigError>;

bool IsValidServerName(std::string_view name) {
  return !name.empty() && name.size() <= 63 && std::all_of(name.begin(), name.end(), [](unsigned char c) {
    return (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9') || c == '-' || c == '_' ||
           c == '.';
  });
}

// "host:port" or "[v6]:port" with a port in 1..65535 and no spaces.
bool IsHostPort(std::string_view address) {
  const auto colon = address.rfind(':');
  if (colon == std::string_view::npos || colon == 0 || colon + 1 == address.size()) return false;
  if (address.find_first_of(" \t") != std::string_view::npos) return false;
  const std::string_view port = address.substr(colon + 1);
  if (port.size() > 5 || !std::all_of(port.begin(), port.end(), [](char c) { return c >= '0' && c <= '9'; })) {
    return false;
  }
  const int value = std::stoi(std::string(port));
  return value >= 1 && value <= 65535;
}

}  // namespace

const DirectoryEntry* ServerDirectory::Find(std::string_view name) const {
  const auto found = std::find_if(servers.begin(), servers.end(), [&](const auto& s) { return s.name == name; });
  return found == servers.end() ? nullptr : &*found;
}

ServerDirectory ParseServerDirectory(std::string_view text, std::string_view origin) {
  const Checker check(origin);
  const toml::table root = check.Parse(text);
  check.OnlyKeys(root, {"server"}, "the directory");
  const toml::array* servers = check.Array(root, "server");
  if (!servers || servers->empty()) check.Fail("no [[server]]: a directory lists at least one server");
  ServerDirectory directory;
  std::set<std::string> names, addresses;
  for (const auto& node : *servers) {
    const auto* t = node.as_table();
    if (!t) check.Fail(node, "each [[server]] must be a table");
    check.OnlyKeys(*t, {"name", "address"}, "[[server]]");
    DirectoryEntry entry{check.String(*t, "name", "[[server]]", true), check.String(*t, "address", "[[server]]", true)};
    if (!IsValidServerName(entry.name)) {
      check.Fail(*t->get("name"), "server name '" + entry.name + "' must be 1-63 of [A-Za-z0-9_.-]");
    }
    if (!IsHostPort(entry.address)) {
      check.Fail(*t->get("address"),
                 "address '" + entry.address + "' of server '" + entry.name + "' must be host:port (port 1-65535)");
    }
    if (!names.insert(entry.name).second) check.Fail(*t, "server '" + entry.name + "' is listed twice");
    if (!addresses.insert(entry.address).second) {
      check.Fail(*t, "address '" + entry.address + "' is listed twice (server '" + entry.name + "')");
    }
    directory.servers.push_back(std::move(entry));
  }
  return directory;
}

ServerDirectory LoadServerDirectory(const std::string& path) {
  return ParseServerDirectory(ReadConfigFile<ClassConfigError>(path, "server directory"), path);
}

}  // namespace hapsim::service
