// hapsim-bridge --join SERVER: before its devices stream, the bridge asks
// the site's servers where each session runs (SessionService.Locate, any
// server of the site will do) and joins it there (JoinSession: the server
// checks the trainee's token and says which DDS domain the session is on).
// Kept behind this plain interface so the bridge's DDS code never sees gRPC.
#pragma once
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "hapsim/common/flags.h"

namespace hapsim::bridge {

class SessionJoiner {
 public:
  SessionJoiner();
  ~SessionJoiner();
  // --join and the connection flags (--token, --token-file, --tls-*).
  void AddFlags(common::Flags* flags);
  bool enabled() const;
  // Locates and joins every session; the DDS domain they share. Logs where
  // each runs. Throws std::runtime_error naming the session and the reason.
  std::uint32_t JoinAll(const std::vector<std::string>& sessions);

 private:
  struct Flags;
  std::unique_ptr<Flags> flags_;
};

}  // namespace hapsim::bridge
