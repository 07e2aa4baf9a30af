// Blocking SessionService calls for command-line tools (hapsim-ctl,
// hapsim-load): each call has its own deadline; a failure reads as
// "CODE: message" through DescribeStatus.
#pragma once
#include <memory>
#include <string>

#include <grpcpp/grpcpp.h>

#include "hapsim/v1/session.grpc.pb.h"
#include "hapsim/viewer/connection.h"

namespace hapsim::viewer {

class SessionClient {
 public:
  explicit SessionClient(const std::string& address, double call_timeout_s = 10.0);
  // Throws std::runtime_error for unreadable TLS files (MakeChannel).
  explicit SessionClient(const Connection& connection, double call_timeout_s = 10.0);
  grpc::Status Create(const v1::CreateSessionRequest& request, v1::SessionInfo* info);
  grpc::Status Get(const std::string& session_id, v1::SessionInfo* info);
  grpc::Status Close(const std::string& session_id);
  enum class Control { kPause, kResume, kReset };
  grpc::Status Apply(Control control, const std::string& session_id, v1::SessionInfo* info);

 private:
  void SetDeadline(grpc::ClientContext* context) const;  // and the token
  std::unique_ptr<v1::SessionService::Stub> stub_;
  std::string token_;
  double call_timeout_s_;
};

// "ALREADY_EXISTS: session 'x' exists", "UNAVAILABLE: failed to connect ...".
std::string DescribeStatus(const grpc::Status& status);

// Parses "KEY=NUMBER" into (*params)[KEY]; false (params untouched) when malformed.
bool AddSceneParam(const std::string& key_equals_number, google::protobuf::Map<std::string, double>* params);

}  // namespace hapsim::viewer
