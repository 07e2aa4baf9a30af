#include "hapsim/service/viewer_service.h"

#include <cmath>

#include <spdlog/spdlog.h>

#include "hapsim/service/viewer_link.h"

namespace hapsim::service {

namespace {

using hapsim::v1::Frame;

// Ends a Subscribe call at once with an error (unknown session, bad request).
class RejectReactor final : public grpc::ServerWriteReactor<Frame> {
 public:
  explicit RejectReactor(const grpc::Status& status) { Finish(status); }
  void OnDone() override { delete this; }
};

class SubscribeReactor final : public grpc::ServerWriteReactor<Frame>, public ViewerLink::Stream {
 public:
  SubscribeReactor(std::shared_ptr<Session> session, std::shared_ptr<ViewerLink> link)
      : session_(std::move(session)), link_(std::move(link)) {
    link_->Attach(this);
    session_->AddViewer(link_);
    spdlog::info("viewer '{}' subscribed to session '{}'", link_->name(), session_->id());
  }

  void StartFrameWrite(const Frame* frame) override { StartWrite(frame); }
  void FinishStream(const grpc::Status& status) override { Finish(status); }

  void OnWriteDone(bool ok) override { link_->OnWriteDone(ok); }
  void OnCancel() override { link_->OnCancelled(); }
  void OnDone() override {
    link_->Detach();
    session_->RemoveViewer(link_.get());
    spdlog::info("viewer '{}' left session '{}' after {} frames, {} bytes", link_->name(), session_->id(),
                 link_->frames_sent(), link_->bytes_sent());
    delete this;
  }

 private:
  std::shared_ptr<Session> session_;
  std::shared_ptr<ViewerLink> link_;
};

}  // namespace

grpc::ServerWriteReactor<Frame>* ViewerServiceImpl::Subscribe(grpc::CallbackServerContext* context,
                                                              const hapsim::v1::SubscribeRequest* request) {
  auto session = registry_->Find(request->session_id());
  if (!session) {
    return new RejectReactor(grpc::Status(grpc::StatusCode::NOT_FOUND,
                                          "no session '" + request->session_id().substr(0, 80) + "'"));
  }
  const double rate = request->max_rate_hz();
  if (!std::isfinite(rate) || rate < 0.0) {
    return new RejectReactor(grpc::Status(grpc::StatusCode::INVALID_ARGUMENT, "max_rate_hz must be >= 0"));
  }
  std::string name = request->viewer_name().empty() ? context->peer() : request->viewer_name().substr(0, 80);
  auto link = std::make_shared<ViewerLink>(std::move(name), rate, quantum_m_);
  return new SubscribeReactor(std::move(session), std::move(link));
}

}  // namespace hapsim::service
