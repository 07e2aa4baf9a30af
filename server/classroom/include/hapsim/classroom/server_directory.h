// The servers of a site (--directory FILE, TOML): which hapsim-servers
// exist and where their gRPC listens, so any of them can say where a
// session runs (SessionService.Locate). A static map, kept by whoever runs
// the site — a Kubernetes StatefulSet's stable pod names fit it
// (hapsim-0.hapsim:50051, ...); there is no election and no shared state.
//
//   [[server]]
//   name = "hapsim-0"                 # this server's --server-name
//   address = "hapsim-0.hapsim:50051" # host:port clients and the other servers dial
//   [[server]]
//   name = "hapsim-1"
//   address = "hapsim-1.hapsim:50051"
#pragma once
#include <string>
#include <string_view>
#include <vector>

#include "hapsim/classroom/class_config.h"  // ClassConfigError

namespace hapsim::service {

struct DirectoryEntry {
  std::string name;     // [A-Za-z0-9_.-]{1,63}
  std::string address;  // host:port
};

struct ServerDirectory {
  std::vector<DirectoryEntry> servers;
  const DirectoryEntry* Find(std::string_view name) const;  // nullptr: not listed
};

// Parses and checks a directory: TOML syntax, known keys only, at least one
// server, valid unique names, "host:port" addresses (port 1..65535), no
// address listed twice. Throws ClassConfigError naming the first problem
// ("FILE:LINE:COL: what").
ServerDirectory ParseServerDirectory(std::string_view toml_text, std::string_view origin);
ServerDirectory LoadServerDirectory(const std::string& path);

}  // namespace hapsim::service
