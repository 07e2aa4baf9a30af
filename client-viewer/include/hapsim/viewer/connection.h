// How a client reaches a hapsim-server: address, bearer token and TLS files
// (docs/classroom.md). Shared by hapsim-ctl, hapsim-viewer and hapsim-load,
// so every client takes the same --token/--tls-* flags.
#pragma once
#include <memory>
#include <string>

#include <grpcpp/grpcpp.h>

#include "hapsim/common/flags.h"

namespace hapsim::viewer {

struct Connection {
  std::string address = "127.0.0.1:50051";
  std::string token;            // bearer token; "" sends none (development-mode servers)
  std::string tls_ca_file;      // "" plain TCP; else TLS, trusting only this CA's server certificates
  std::string tls_cert_file;    // client certificate (for servers started with --tls-client-ca)
  std::string tls_key_file;     // its private key
  std::string tls_server_name;  // name to check in the server's certificate instead of the address's host
};

// Throws std::runtime_error if a TLS file cannot be read or only one of the
// client certificate and key is given.
std::shared_ptr<grpc::Channel> MakeChannel(const Connection& connection,
                                           const grpc::ChannelArguments& args = grpc::ChannelArguments());

// Puts the token (if any) in the call's "authorization" metadata.
void AddToken(grpc::ClientContext* context, const std::string& token);

// Declares --token, --token-file, --tls-ca, --tls-cert, --tls-key and
// --tls-server-name; FinishConnectionFlags then resolves the token
// (--token-file, else --token, else the HAPSIM_TOKEN environment variable).
struct ConnectionFlags {
  std::string token_file;
};
void AddConnectionFlags(common::Flags* flags, Connection* connection, ConnectionFlags* extra);
// false with *error set when the token file cannot be read or is empty.
bool FinishConnectionFlags(const ConnectionFlags& extra, Connection* connection, std::string* error);

}  // namespace hapsim::viewer
