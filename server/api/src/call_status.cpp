#include "hapsim/api/call_status.h"

namespace hapsim::service {

using grpc::Status;
using grpc::StatusCode;

Status ToGrpcStatus(const ServiceError& e) {
  switch (e.code()) {
    case ErrorCode::kInvalidArgument:
      return {StatusCode::INVALID_ARGUMENT, e.what()};
    case ErrorCode::kNotFound:
      return {StatusCode::NOT_FOUND, e.what()};
    case ErrorCode::kAlreadyExists:
      return {StatusCode::ALREADY_EXISTS, e.what()};
    case ErrorCode::kResourceExhausted:
      return {StatusCode::RESOURCE_EXHAUSTED, e.what()};
    case ErrorCode::kFailedPrecondition:
      return {StatusCode::FAILED_PRECONDITION, e.what()};
    case ErrorCode::kUnauthenticated:
      return {StatusCode::UNAUTHENTICATED, e.what()};
    case ErrorCode::kPermissionDenied:
      return {StatusCode::PERMISSION_DENIED, e.what()};
    case ErrorCode::kUnavailable:
      return {StatusCode::UNAVAILABLE, e.what()};
  }
  return {StatusCode::INTERNAL, e.what()};
}

std::optional<std::string> AuthorizationOf(const grpc::ServerContextBase* context) {
  if (!context) return std::nullopt;
  const auto& metadata = context->client_metadata();
  const auto found = metadata.find("authorization");
  if (found == metadata.end()) return std::nullopt;
  return std::string(found->second.data(), found->second.size());
}

std::optional<Principal> AuthenticateCall(const AccessPolicy& policy, const grpc::ServerContextBase* context) {
  if (!policy.enabled()) return std::nullopt;
  const auto authorization = AuthorizationOf(context);
  return policy.Authenticate(authorization ? &*authorization : nullptr);
}

const AccessPolicy& OpenAccessPolicy() {
  static const AccessPolicy open;
  return open;
}

}  // namespace hapsim::service
