#include "hapsim/viewer/connection.h"

#include <cstdlib>
#include <fstream>
#include <sstream>
#include <stdexcept>

namespace hapsim::viewer {

namespace {

std::string ReadFile(const std::string& path, const char* what) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw std::runtime_error(std::string("cannot read ") + what + " " + path);
  std::ostringstream text;
  text << in.rdbuf();
  return text.str();
}

std::string Trimmed(std::string s) {
  while (!s.empty() && (s.back() == '\n' || s.back() == '\r' || s.back() == ' ' || s.back() == '\t')) s.pop_back();
  std::size_t start = 0;
  while (start < s.size() && (s[start] == ' ' || s[start] == '\t')) ++start;
  return s.substr(start);
}

}  // namespace

std::shared_ptr<grpc::Channel> MakeChannel(const Connection& c, const grpc::ChannelArguments& args_in) {
  grpc::ChannelArguments args = args_in;
  if (c.tls_ca_file.empty()) {
    if (!c.tls_cert_file.empty() || !c.tls_key_file.empty()) {
      throw std::runtime_error("a client certificate (--tls-cert/--tls-key) needs TLS: give --tls-ca too");
    }
    return grpc::CreateCustomChannel(c.address, grpc::InsecureChannelCredentials(), args);
  }
  if (c.tls_cert_file.empty() != c.tls_key_file.empty()) {
    throw std::runtime_error("a client certificate needs both --tls-cert and --tls-key");
  }
  grpc::SslCredentialsOptions ssl;
  ssl.pem_root_certs = ReadFile(c.tls_ca_file, "TLS CA");
  if (!c.tls_cert_file.empty()) {
    ssl.pem_cert_chain = ReadFile(c.tls_cert_file, "TLS client certificate");
    ssl.pem_private_key = ReadFile(c.tls_key_file, "TLS client key");
  }
  if (!c.tls_server_name.empty()) args.SetSslTargetNameOverride(c.tls_server_name);
  return grpc::CreateCustomChannel(c.address, grpc::SslCredentials(ssl), args);
}

void AddToken(grpc::ClientContext* context, const std::string& token) {
  if (!token.empty()) context->AddMetadata("authorization", "Bearer " + token);
}

void AddConnectionFlags(common::Flags* flags, Connection* c, ConnectionFlags* extra) {
  flags->Add("token", &c->token, "bearer token for a server with a class config (visible in ps: prefer --token-file "
                                 "or HAPSIM_TOKEN)");
  flags->Add("token-file", &extra->token_file, "read the bearer token from this file");
  flags->Add("tls-ca", &c->tls_ca_file, "connect over TLS, trusting server certificates of this PEM CA");
  flags->Add("tls-cert", &c->tls_cert_file, "PEM client certificate (servers started with --tls-client-ca)");
  flags->Add("tls-key", &c->tls_key_file, "PEM private key of --tls-cert");
  flags->Add("tls-server-name", &c->tls_server_name, "check this name in the server's certificate");
}

bool FinishConnectionFlags(const ConnectionFlags& extra, Connection* c, std::string* error) {
  if (!extra.token_file.empty()) {
    try {
      c->token = Trimmed(ReadFile(extra.token_file, "token file"));
    } catch (const std::exception& e) {
      *error = e.what();
      return false;
    }
    if (c->token.empty()) {
      *error = "token file " + extra.token_file + " is empty";
      return false;
    }
  } else if (c->token.empty()) {
    if (const char* env = std::getenv("HAPSIM_TOKEN")) c->token = Trimmed(env);
  }
  return true;
}

}  // namespace hapsim::viewer
