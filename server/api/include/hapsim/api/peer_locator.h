// Asks the other servers of the site's directory where a session runs
// (their SessionService.Locate, local_only): all at once, each bounded by
// one timeout, so one dead server costs a Locate at most that long. The
// caller's "authorization" goes along unchanged — each server judges its
// own tokens, and no server holds another's secrets.
#pragma once
#include <grpcpp/grpcpp.h>

#include <chrono>
#include <memory>
#include <string>
#include <vector>

#include "hapsim/classroom/server_directory.h"
#include "hapsim/v1/session.grpc.pb.h"

namespace hapsim::service {

struct PeerAnswer {
  const DirectoryEntry* server = nullptr;
  grpc::Status status;  // OK: it hosts the session; NOT_FOUND: it does not; else it did not answer (or refused)
  hapsim::v1::LocateResponse response;
};

class PeerLocator {
 public:
  // credentials: how to dial the other servers (TLS with the site's CA, or
  // plain). self_name: this server's name, left out of the servers asked.
  PeerLocator(ServerDirectory directory, std::string self_name, std::shared_ptr<grpc::ChannelCredentials> credentials,
              std::chrono::milliseconds timeout);

  const std::string& self_name() const { return self_name_; }
  const DirectoryEntry* self() const { return directory_.Find(self_name_); }  // nullptr: not listed
  const ServerDirectory& directory() const { return directory_; }
  std::chrono::milliseconds timeout() const { return timeout_; }

  // Every other server's answer, in directory order. `authorization`: the
  // caller's metadata value (nullptr: none). Waits at most the timeout, or
  // until `deadline` if that comes first.
  std::vector<PeerAnswer> AskAll(const std::string& session_id, const std::string* authorization,
                                 std::chrono::system_clock::time_point deadline) const;

 private:
  struct Peer {
    const DirectoryEntry* server;
    std::unique_ptr<hapsim::v1::SessionService::Stub> stub;
  };
  ServerDirectory directory_;
  std::string self_name_;
  std::chrono::milliseconds timeout_;
  std::vector<Peer> peers_;  // the directory but this server; channels connect lazily and reconnect on their own
};

}  // namespace hapsim::service
