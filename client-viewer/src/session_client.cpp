#include "hapsim/viewer/session_client.h"

#include <chrono>
#include <cstdlib>

namespace hapsim::viewer {

SessionClient::SessionClient(const std::string& address, double call_timeout_s)
    : stub_(v1::SessionService::NewStub(grpc::CreateChannel(address, grpc::InsecureChannelCredentials()))),
      call_timeout_s_(call_timeout_s) {}

SessionClient::SessionClient(const Connection& connection, double call_timeout_s)
    : stub_(v1::SessionService::NewStub(MakeChannel(connection))), token_(connection.token),
      call_timeout_s_(call_timeout_s) {}

void SessionClient::SetDeadline(grpc::ClientContext* context) const {
  context->set_deadline(std::chrono::system_clock::now() +
                        std::chrono::duration_cast<std::chrono::milliseconds>(
                            std::chrono::duration<double>(call_timeout_s_)));
  AddToken(context, token_);
}

grpc::Status SessionClient::Create(const v1::CreateSessionRequest& request, v1::SessionInfo* info) {
  grpc::ClientContext context;
  SetDeadline(&context);
  return stub_->CreateSession(&context, request, info);
}

grpc::Status SessionClient::Get(const std::string& session_id, v1::SessionInfo* info) {
  grpc::ClientContext context;
  SetDeadline(&context);
  v1::SessionRef ref;
  ref.set_session_id(session_id);
  return stub_->GetSession(&context, ref, info);
}

grpc::Status SessionClient::Close(const std::string& session_id) {
  grpc::ClientContext context;
  SetDeadline(&context);
  v1::SessionRef ref;
  ref.set_session_id(session_id);
  v1::CloseSessionResponse response;
  return stub_->CloseSession(&context, ref, &response);
}

grpc::Status SessionClient::Apply(Control control, const std::string& session_id, v1::SessionInfo* info) {
  grpc::ClientContext context;
  SetDeadline(&context);
  v1::SessionRef ref;
  ref.set_session_id(session_id);
  switch (control) {
    case Control::kPause: return stub_->PauseSession(&context, ref, info);
    case Control::kResume: return stub_->ResumeSession(&context, ref, info);
    case Control::kReset: return stub_->ResetSession(&context, ref, info);
  }
  return grpc::Status(grpc::StatusCode::INVALID_ARGUMENT, "unknown control");
}

std::string DescribeStatus(const grpc::Status& status) {
  static constexpr const char* kNames[] = {
      "OK",        "CANCELLED",         "UNKNOWN",      "INVALID_ARGUMENT", "DEADLINE_EXCEEDED", "NOT_FOUND",
      "ALREADY_EXISTS", "PERMISSION_DENIED", "RESOURCE_EXHAUSTED", "FAILED_PRECONDITION", "ABORTED",
      "OUT_OF_RANGE", "UNIMPLEMENTED", "INTERNAL", "UNAVAILABLE", "DATA_LOSS", "UNAUTHENTICATED"};
  const int code = static_cast<int>(status.error_code());
  const std::string name = code >= 0 && code < 17 ? kNames[code] : "code " + std::to_string(code);
  return name + ": " + status.error_message();
}

bool AddSceneParam(const std::string& kv, google::protobuf::Map<std::string, double>* params) {
  const auto eq = kv.find('=');
  if (eq == std::string::npos || eq == 0 || eq + 1 == kv.size()) return false;
  char* end = nullptr;
  const double value = std::strtod(kv.c_str() + eq + 1, &end);
  if (!end || *end != '\0') return false;
  (*params)[kv.substr(0, eq)] = value;
  return true;
}

}  // namespace hapsim::viewer
