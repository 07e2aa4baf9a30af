// What every gRPC handler of the server does first and last: find who calls
// (the "authorization" metadata, through the AccessPolicy), and turn what
// went wrong into a status — a client's mistake never escapes as an
// exception, and the runtime's ServiceErrors map to gRPC codes here only.
#pragma once
#include <grpcpp/grpcpp.h>
#include <spdlog/spdlog.h>

#include <exception>
#include <optional>
#include <string>

#include "hapsim/classroom/access_policy.h"
#include "hapsim/runtime/errors.h"

namespace hapsim::service {

grpc::Status ToGrpcStatus(const ServiceError& e);

// The call's "authorization" metadata value, if sent (what a server passes
// on unchanged when it asks another server for its caller).
std::optional<std::string> AuthorizationOf(const grpc::ServerContextBase* context);

// The caller behind a gRPC call's metadata ("authorization"), for every
// service: nullopt in development mode; throws ServiceError(kUnauthenticated).
std::optional<Principal> AuthenticateCall(const AccessPolicy& policy, const grpc::ServerContextBase* context);

// The policy of a service given none: development mode, everything allowed.
const AccessPolicy& OpenAccessPolicy();

// Runs a handler body, turning bad input into a status and anything else
// into INTERNAL (logged with the call's name).
template <class F>
grpc::Status Guarded(const char* rpc, F&& body) {
  try {
    body();
    return grpc::Status::OK;
  } catch (const ServiceError& e) {
    return ToGrpcStatus(e);
  } catch (const std::exception& e) {
    spdlog::error("{} failed: {}", rpc, e.what());
    return {grpc::StatusCode::INTERNAL, std::string(rpc) + " failed: " + e.what()};
  }
}

}  // namespace hapsim::service
