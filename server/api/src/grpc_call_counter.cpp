#include "hapsim/api/grpc_call_counter.h"

#include <cstring>

namespace hapsim::service {
namespace {

class CountingInterceptor final : public grpc::experimental::Interceptor {
 public:
  CountingInterceptor(GrpcCallCounter* counter, const char* method) : counter_(counter), method_(method) {}
  void Intercept(grpc::experimental::InterceptorBatchMethods* methods) override {
    if (methods->QueryInterceptionHookPoint(grpc::experimental::InterceptionHookPoints::PRE_SEND_STATUS)) {
      counter_->Record(method_, static_cast<int>(methods->GetSendStatus().error_code()));
    }
    methods->Proceed();
  }

 private:
  GrpcCallCounter* counter_;
  const char* method_;
};

class Factory final : public grpc::experimental::ServerInterceptorFactoryInterface {
 public:
  explicit Factory(GrpcCallCounter* counter) : counter_(counter) {}
  grpc::experimental::Interceptor* CreateServerInterceptor(grpc::experimental::ServerRpcInfo* info) override {
    return new CountingInterceptor(counter_, info->method());
  }

 private:
  GrpcCallCounter* counter_;
};

}  // namespace

void GrpcCallCounter::Record(const char* method, int code) {
  // Only our own services get their own label: an unknown method name is a
  // client's choice and must not grow the map.
  const std::string name = method && std::strncmp(method, "/hapsim.v1.", 11) == 0 ? method : "other";
  if (code < 0 || code >= kCodes) code = 2;  // UNKNOWN
  std::lock_guard lock(mutex_);
  auto it = counts_.find(name);
  if (it == counts_.end()) it = counts_.emplace(name, std::array<std::uint64_t, kCodes>{}).first;
  ++it->second[static_cast<std::size_t>(code)];
}

std::map<std::string, std::array<std::uint64_t, GrpcCallCounter::kCodes>> GrpcCallCounter::Snapshot() const {
  std::lock_guard lock(mutex_);
  return counts_;
}

std::unique_ptr<grpc::experimental::ServerInterceptorFactoryInterface> GrpcCallCounter::MakeInterceptorFactory() {
  return std::make_unique<Factory>(this);
}

const char* GrpcCodeName(int code) {
  static const char* const kNames[GrpcCallCounter::kCodes] = {
      "OK",        "CANCELLED",          "UNKNOWN",        "INVALID_ARGUMENT", "DEADLINE_EXCEEDED", "NOT_FOUND",
      "ALREADY_EXISTS", "PERMISSION_DENIED", "RESOURCE_EXHAUSTED", "FAILED_PRECONDITION", "ABORTED", "OUT_OF_RANGE",
      "UNIMPLEMENTED", "INTERNAL", "UNAVAILABLE", "DATA_LOSS", "UNAUTHENTICATED"};
  return code >= 0 && code < GrpcCallCounter::kCodes ? kNames[code] : "UNKNOWN";
}

}  // namespace hapsim::service
