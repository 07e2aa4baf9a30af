// gRPC ViewerService: Subscribe(stream ViewerMessage) -> stream Frame, on the
// callback API with one small reactor per stream and at most one write in
// flight. The first message names the session; the rest are acks.
#pragma once
#include <cstdint>

#include "hapsim/classroom/access_policy.h"
#include "hapsim/runtime/session_registry.h"
#include "hapsim/streaming/viewer_hub.h"
#include "hapsim/v1/viewer.grpc.pb.h"

namespace hapsim::service {

// Most frames a viewer may leave unacknowledged (SubscribeRequest.ack_window).
inline constexpr std::uint32_t kMaxAckWindow = 64;

// The SubscribeRequest's own fields, before any session is looked up: OK, or
// INVALID_ARGUMENT naming the field (max_rate_hz, ack_window).
grpc::Status CheckSubscribeRequest(const hapsim::v1::SubscribeRequest& request);

class ViewerServiceImpl final : public hapsim::v1::ViewerService::CallbackService {
 public:
  // policy: who may view which session (nullptr: development mode).
  ViewerServiceImpl(const SessionRegistry* registry, ViewerHub* hub, double quantum_m,
                    const AccessPolicy* policy = nullptr)
      : registry_(registry), hub_(hub), quantum_m_(quantum_m), policy_(policy) {}

  grpc::ServerBidiReactor<hapsim::v1::ViewerMessage, hapsim::v1::Frame>* Subscribe(
      grpc::CallbackServerContext* context) override;

 private:
  const SessionRegistry* registry_;
  ViewerHub* hub_;
  double quantum_m_;
  const AccessPolicy* policy_;
};

}  // namespace hapsim::service
