// Counts every gRPC call the server answers, by method and status code (for
// /metrics: hapsim_grpc_calls_total). A server interceptor sees each call's
// status just before it is sent (PRE_SEND_STATUS), so refusals by the
// handlers count as well as successes. Bounded: one counter per (known
// method or "other", code).
#pragma once
#include <array>
#include <atomic>
#include <map>
#include <memory>
#include <mutex>
#include <string>

#include <grpcpp/support/server_interceptor.h>

namespace hapsim::service {

class GrpcCallCounter {
 public:
  static constexpr int kCodes = 17;  // grpc::StatusCode OK .. UNAUTHENTICATED

  void Record(const char* method, int code);
  // method -> counts by code (a copy, for the metrics text).
  std::map<std::string, std::array<std::uint64_t, kCodes>> Snapshot() const;
  // The interceptor factory to give grpc::ServerBuilder.
  std::unique_ptr<grpc::experimental::ServerInterceptorFactoryInterface> MakeInterceptorFactory();

 private:
  mutable std::mutex mutex_;
  std::map<std::string, std::array<std::uint64_t, kCodes>> counts_;
};

// gRPC's name of a status code ("OK", "INVALID_ARGUMENT", ...).
const char* GrpcCodeName(int code);

}  // namespace hapsim::service
