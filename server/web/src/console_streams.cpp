#include "console_streams.h"

namespace hapsim::web {

void ClassWatch::Start(const hapsim::v1::WatchClassRequest& request) {
  request_ = request;
  Prepare();
  owner_->sessions().async()->WatchClass(&context_, &request_, this);
  Hold();
  StartRead(&incoming_);
  StartCall();
}

void TraineeView::Start(const hapsim::v1::SubscribeRequest& request) {
  Prepare();
  owner_->viewers().async()->Subscribe(&context_, this);
  Hold();
  *outgoing_.mutable_subscribe() = request;
  write_busy_ = true;
  StartWrite(&outgoing_);
  StartRead(&incoming_);
  StartCall();
}

void TraineeView::Ack(const hapsim::v1::ViewerAck& ack) {
  std::lock_guard lock(hold_mutex_);
  if (released_) return;  // the call may be finishing: no new operation
  pending_ack_ = ack;
  if (!write_busy_) WriteAckLocked();
}

void TraineeView::OnWriteDone(bool ok) {
  std::lock_guard lock(hold_mutex_);
  write_busy_ = false;
  if (ok && pending_ack_ && !released_) WriteAckLocked();
}

void TraineeView::WriteAckLocked() {
  outgoing_.Clear();
  *outgoing_.mutable_ack() = *pending_ack_;
  pending_ack_.reset();
  write_busy_ = true;
  StartWrite(&outgoing_);
}

}  // namespace hapsim::web
