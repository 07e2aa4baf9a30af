// Bad input from a client becomes a ServiceError with a code the gRPC layer
// maps to a status; the registry and sessions stay free of gRPC types.
#pragma once
#include <stdexcept>
#include <string>

namespace hapsim::service {

enum class ErrorCode {
  kInvalidArgument,
  kNotFound,
  kAlreadyExists,
  kResourceExhausted,
  kFailedPrecondition,
  kUnauthenticated,   // no token, or one the server does not know
  kPermissionDenied,  // a known caller whose role or class does not allow the call
  kUnavailable,       // the answer depends on another server that did not answer
};

class ServiceError : public std::runtime_error {
 public:
  ServiceError(ErrorCode code, const std::string& message) : std::runtime_error(message), code_(code) {}
  ErrorCode code() const { return code_; }

 private:
  ErrorCode code_;
};

}  // namespace hapsim::service
