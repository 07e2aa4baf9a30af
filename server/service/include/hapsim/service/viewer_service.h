// gRPC ViewerService: Subscribe(session) -> stream Frame, on the callback API
// with one small reactor per stream and at most one write in flight.
#pragma once
#include "hapsim/service/session_registry.h"
#include "hapsim/v1/viewer.grpc.pb.h"

namespace hapsim::service {

class ViewerServiceImpl final : public hapsim::v1::ViewerService::CallbackService {
 public:
  ViewerServiceImpl(SessionRegistry* registry, double quantum_m) : registry_(registry), quantum_m_(quantum_m) {}

  grpc::ServerWriteReactor<hapsim::v1::Frame>* Subscribe(grpc::CallbackServerContext* context,
                                                         const hapsim::v1::SubscribeRequest* request) override;

 private:
  SessionRegistry* registry_;
  double quantum_m_;
};

}  // namespace hapsim::service
