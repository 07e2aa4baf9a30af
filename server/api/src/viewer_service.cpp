#include "hapsim/api/viewer_service.h"

#include <spdlog/spdlog.h>

#include <cmath>
#include <mutex>

#include "hapsim/api/call_status.h"
#include "hapsim/common/clock.h"
#include "hapsim/streaming/viewer_link.h"

namespace hapsim::service {

namespace {

using hapsim::v1::Frame;
using hapsim::v1::ViewerMessage;

// One Subscribe stream. Reads the subscribe request, then keeps reading acks
// for the whole stream; frames are written by the frame pump via the link.
class SubscribeReactor final : public grpc::ServerBidiReactor<ViewerMessage, Frame>, public ViewerLink::Stream {
 public:
  // caller: who the call's token names (checked against the session once the
  // SubscribeRequest names it); auth_error: the token was refused.
  SubscribeReactor(const SessionRegistry* registry, ViewerHub* hub, double quantum_m, std::string peer,
                   const AccessPolicy* policy, std::optional<Principal> caller, grpc::Status auth_error)
      : registry_(registry), hub_(hub), quantum_m_(quantum_m), peer_(std::move(peer)), policy_(policy),
        caller_(std::move(caller)), auth_error_(std::move(auth_error)) {
    if (!auth_error_.ok()) {  // refused before anything is read
      Finish(auth_error_);
      return;
    }
    StartRead(&incoming_);
  }

  void StartFrameWrite(const Frame* frame) override { StartWrite(frame); }
  void FinishStream(const grpc::Status& status) override { Finish(status); }

  void OnReadDone(bool ok) override {
    if (!ok) {  // the viewer closed its side or went away
      if (!link_) Finish(grpc::Status(grpc::StatusCode::INVALID_ARGUMENT, "no SubscribeRequest received"));
      return;
    }
    if (!link_) {
      const grpc::Status status = Subscribe();
      if (!status.ok()) {
        Finish(status);
        return;
      }
    } else if (incoming_.has_ack()) {
      link_->OnAck(incoming_.ack().applied_seq(), incoming_.ack().held_us(), common::SteadyNowNs());
    }
    StartRead(&incoming_);
  }
  void OnWriteDone(bool ok) override {
    if (auto link = Link()) link->OnWriteDone(ok);
  }
  void OnCancel() override {
    if (auto link = Link()) link->OnCancelled();
  }
  void OnDone() override {
    if (link_) {
      link_->Detach();
      hub_->Remove(*session_, link_.get());
      spdlog::info("viewer '{}' left session '{}' after {} frames, {} bytes, {} snapshots coalesced (slow viewer)",
                   link_->name(), session_->id(), link_->frames_sent(), link_->bytes_sent(),
                   link_->snapshots_coalesced());
    }
    delete this;
  }

 private:
  // Read and write reactions may run on different threads: link_ is set once
  // (first read) and read elsewhere under this mutex.
  std::shared_ptr<ViewerLink> Link() {
    std::lock_guard lock(link_mutex_);
    return link_;
  }

  grpc::Status Subscribe() {
    if (!incoming_.has_subscribe()) {
      return {grpc::StatusCode::INVALID_ARGUMENT, "the first message must be a SubscribeRequest"};
    }
    const auto& req = incoming_.subscribe();
    if (policy_) {
      try {
        policy_->Authorize(caller_, Action::kView, req.session_id());
      } catch (const ServiceError& e) {
        return ToGrpcStatus(e);
      }
    }
    if (grpc::Status fields = CheckSubscribeRequest(req); !fields.ok()) return fields;
    session_ = registry_->Find(req.session_id());
    if (!session_) return {grpc::StatusCode::NOT_FOUND, "no session '" + req.session_id().substr(0, 80) + "'"};
    std::string name = req.viewer_name().empty() ? peer_ : req.viewer_name().substr(0, 80);
    auto link = std::make_shared<ViewerLink>(std::move(name), req.max_rate_hz(), quantum_m_, req.ack_window());
    link->Attach(this);
    {
      std::lock_guard lock(link_mutex_);
      link_ = link;
    }
    hub_->Add(session_, link_);
    spdlog::info("viewer '{}' subscribed to session '{}' (ack window {})", link_->name(), session_->id(),
                 req.ack_window());
    return grpc::Status::OK;
  }

  const SessionRegistry* registry_;
  ViewerHub* hub_;
  double quantum_m_;
  std::string peer_;
  const AccessPolicy* policy_;
  std::optional<Principal> caller_;
  grpc::Status auth_error_;
  ViewerMessage incoming_;
  std::shared_ptr<Session> session_;
  std::mutex link_mutex_;
  std::shared_ptr<ViewerLink> link_;
};

}  // namespace

grpc::Status CheckSubscribeRequest(const hapsim::v1::SubscribeRequest& request) {
  const double rate = request.max_rate_hz();
  // A positive rate below 0.01 Hz (one frame per 100 s) would overflow the
  // frame interval in nanoseconds; nobody watches a session that slowly.
  if (!std::isfinite(rate) || rate < 0.0 || (rate > 0.0 && rate < 0.01)) {
    return {grpc::StatusCode::INVALID_ARGUMENT, "max_rate_hz must be 0 (the session's frame rate) or >= 0.01"};
  }
  if (request.ack_window() > kMaxAckWindow) {
    return {grpc::StatusCode::INVALID_ARGUMENT, "ack_window must be at most " + std::to_string(kMaxAckWindow)};
  }
  return grpc::Status::OK;
}

grpc::ServerBidiReactor<ViewerMessage, Frame>* ViewerServiceImpl::Subscribe(grpc::CallbackServerContext* context) {
  std::optional<Principal> caller;
  grpc::Status auth_error = grpc::Status::OK;
  if (policy_) {
    try {
      caller = AuthenticateCall(*policy_, context);
    } catch (const ServiceError& e) {
      auth_error = ToGrpcStatus(e);
    }
  }
  return new SubscribeReactor(registry_, hub_, quantum_m_, context->peer(), policy_, std::move(caller),
                              std::move(auth_error));
}

}  // namespace hapsim::service
