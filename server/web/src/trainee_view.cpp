#include "trainee_view.h"

#include <algorithm>

#include "hapsim/common/clock.h"

namespace hapsim::web {

void TraineeView::Start(const hapsim::v1::SubscribeRequest& request) {
  owner_->services().open_calls->Add();
  owner_->Authorize(&context_);
  owner_->viewers().async()->Subscribe(&context_, this);
  AddHold();  // only once bound to its call; released by Cancel or the stream's end
  *outgoing_.mutable_subscribe() = request;
  write_busy_ = true;
  StartWrite(&outgoing_);
  StartRead(&incoming_);
  StartCall();
}

void TraineeView::Cancel() {
  bool holding = false;
  {
    std::lock_guard lock(mutex_);
    holding = !released_;
    released_ = true;
  }
  context_.TryCancel();
  if (holding) RemoveHold();  // last: the end may run inline from here
}

void TraineeView::ReleaseHold() {
  {
    std::lock_guard lock(mutex_);
    if (released_) return;
    released_ = true;
  }
  RemoveHold();  // may run OnDone (and delete this) inline: the last thing touched
}

void TraineeView::OnReadDone(bool ok) {
  if (!ok) {  // the stream ended; OnDone tells why
    ReleaseHold();
    return;
  }
  AddHold();  // until the browser has the frame
  {
    std::lock_guard lock(mutex_);
    read_ns_[incoming_.seq() % kFramesRemembered] = common::SteadyNowNs();
    frames_read_ = incoming_.seq() + 1;
  }
  hapsim::v1::ConsoleEvent event;
  event.mutable_frame()->Swap(&incoming_);
  owner_->SendEvent(event, [this](bool sent) {
    if (sent) StartRead(&incoming_);
    RemoveHold();
  });
}

void TraineeView::Ack(const hapsim::v1::ViewerAck& ack) {
  std::lock_guard lock(mutex_);
  if (released_) return;  // the call may be finishing: no new operation
  pending_ack_ = ack;
  const std::uint64_t seq = ack.applied_seq();
  if (seq < frames_read_ && frames_read_ - seq <= kFramesRemembered) {
    const std::int64_t held_ns = common::SteadyNowNs() - read_ns_[seq % kFramesRemembered];
    pending_ack_->set_held_us(static_cast<std::uint64_t>(std::max<std::int64_t>(held_ns, 0) / 1000));
  }
  if (!write_busy_) WriteAckLocked();
}

void TraineeView::OnWriteDone(bool ok) {
  std::lock_guard lock(mutex_);
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

void TraineeView::OnDone(const grpc::Status& status) {
  owner_->ViewEnded(status, this);
  OpenCalls* calls = owner_->services().open_calls;
  delete this;
  calls->Remove();
}

}  // namespace hapsim::web
