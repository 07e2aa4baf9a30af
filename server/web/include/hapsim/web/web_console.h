// The browser console's endpoint: HTTPS (or plain HTTP on loopback in
// development) serving the web app's files, and a WebSocket at /ws that
// carries the console protocol (hapsim/v1/console.proto). Every request a
// browser makes is answered by the server's own gRPC services over an
// in-process channel with the browser's token, so the access policy, the
// auth-failure metric and the viewer streams' newest-state-wins flow
// control are exactly a gRPC client's. Off unless a listen address is given.
//
// Threads: one I/O thread of its own (HTTP, TLS, WebSocket); gRPC's
// callback threads hand frames and statuses to it. Nothing here runs on a
// tick or takes a lock a tick takes.
#pragma once
#include <grpcpp/grpcpp.h>

#include <cstdint>
#include <memory>
#include <string>

#include "hapsim/classroom/access_policy.h"

namespace hapsim::web {

struct WebConsoleOptions {
  std::string listen_address;  // host:port (port 0: any free port)
  std::string root_dir;        // the built web app (index.html and its bundle)
  // TLS: PEM files, both or neither (then plain HTTP/WebSocket). With
  // client_ca_file, browsers must present a certificate signed by that CA.
  std::string tls_cert_file, tls_key_file, tls_client_ca_file;
  int max_connections = 64;  // WebSocket connections at once; more are refused
  std::string server_version;
};

class WebConsole {
 public:
  // channel: to this server's gRPC services (grpc::Server::InProcessChannel).
  // policy: names the caller in the welcome (nullptr or disabled:
  // development mode); the services check every call themselves.
  // Throws std::runtime_error for an address that cannot be bound or bad
  // TLS files.
  WebConsole(const WebConsoleOptions& options, std::shared_ptr<grpc::Channel> channel,
             const service::AccessPolicy* policy);
  ~WebConsole();  // Stop()
  WebConsole(const WebConsole&) = delete;
  WebConsole& operator=(const WebConsole&) = delete;

  int bound_port() const;
  bool tls() const;
  // Closes every connection (their streams end), waits for their gRPC calls
  // to finish and stops the I/O thread. Idempotent. Must run before the gRPC
  // server shuts down.
  void Stop();

  struct Impl;

 private:
  std::unique_ptr<Impl> impl_;
};

}  // namespace hapsim::web
