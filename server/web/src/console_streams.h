// The two gRPC streams a console connection opens on the server's own
// services: the class view (WatchClass) and the trainee view (Subscribe).
// Each reads one message, hands it to the browser, and reads the next only
// once the browser has been sent it. A hold keeps each reactor alive until
// it is cancelled or its stream ends, so the session may reach it (cancel,
// acks) at any time before that without racing its deletion. A stream is
// created, stored and started on the I/O thread, which is also the only
// thread that cancels it: no cancel comes before its start.
#pragma once
#include <grpcpp/grpcpp.h>

#include <memory>
#include <mutex>
#include <optional>

#include "console_session.h"

namespace hapsim::web {

template <class Reactor, class Message>
class ConsoleStream : public Reactor {
 public:
  virtual ~ConsoleStream() = default;
  // The browser replaced or closed this view, or left: end the call.
  void Cancel() {
    context_.TryCancel();
    ReleaseHold();
  }

  void OnReadDone(bool ok) override {
    if (!ok) {  // the stream ended; OnDone tells why
      ReleaseHold();
      return;
    }
    this->AddHold();  // until the browser has the message
    hapsim::v1::ConsoleEvent event;
    MoveIntoEvent(&incoming_, &event);
    owner_->SendEvent(event, [this](bool sent) {
      if (sent) {
        CountSent();
        this->StartRead(&incoming_);
      }
      this->RemoveHold();
    });
  }

  void OnDone(const grpc::Status& status) override {
    owner_->StreamEnded(name_, status, this);
    OpenCalls* calls = owner_->services().open_calls;
    delete this;
    calls->Remove();
  }

 protected:
  ConsoleStream(std::shared_ptr<ConsoleSession> owner, const char* name) : owner_(std::move(owner)), name_(name) {}
  // A subclass's Start: Prepare(), bind the reactor to its call (stub),
  // Hold() (a reactor's holds exist only once it is bound), then start.
  void Prepare() {
    owner_->services().open_calls->Add();
    owner_->Authorize(&context_);
  }
  void Hold() { this->AddHold(); }  // released by Cancel or the stream's end
  virtual void MoveIntoEvent(Message* message, hapsim::v1::ConsoleEvent* event) = 0;
  virtual void CountSent() = 0;
  void ReleaseHold() {
    {
      std::lock_guard lock(hold_mutex_);
      if (released_) return;
      released_ = true;
    }
    this->RemoveHold();  // may run OnDone (and delete this) inline: the last thing touched
  }

  std::shared_ptr<ConsoleSession> owner_;
  const char* name_;
  grpc::ClientContext context_;
  Message incoming_;
  std::mutex hold_mutex_;  // released_, and a subclass's writes
  bool released_ = false;
};

class ClassWatch final
    : public ConsoleStream<grpc::ClientReadReactor<hapsim::v1::ClassStatus>, hapsim::v1::ClassStatus> {
 public:
  explicit ClassWatch(std::shared_ptr<ConsoleSession> owner) : ConsoleStream(std::move(owner), "class") {}
  void Start(const hapsim::v1::WatchClassRequest& request);

 private:
  void MoveIntoEvent(hapsim::v1::ClassStatus* status, hapsim::v1::ConsoleEvent* event) override {
    event->mutable_class_status()->Swap(status);
  }
  void CountSent() override { owner_->services().counters->statuses_sent.fetch_add(1, std::memory_order_relaxed); }
  hapsim::v1::WatchClassRequest request_;
};

class TraineeView final
    : public ConsoleStream<grpc::ClientBidiReactor<hapsim::v1::ViewerMessage, hapsim::v1::Frame>, hapsim::v1::Frame> {
 public:
  explicit TraineeView(std::shared_ptr<ConsoleSession> owner) : ConsoleStream(std::move(owner), "view") {}
  void Start(const hapsim::v1::SubscribeRequest& request);
  // The browser's newest ack; acks are cumulative, so one waiting is enough.
  void Ack(const hapsim::v1::ViewerAck& ack);
  void OnWriteDone(bool ok) override;

 private:
  void MoveIntoEvent(hapsim::v1::Frame* frame, hapsim::v1::ConsoleEvent* event) override {
    event->mutable_frame()->Swap(frame);
  }
  void CountSent() override { owner_->services().counters->frames_sent.fetch_add(1, std::memory_order_relaxed); }
  void WriteAckLocked();  // hold_mutex_ held

  hapsim::v1::ViewerMessage outgoing_;
  bool write_busy_ = false;
  std::optional<hapsim::v1::ViewerAck> pending_ack_;
};

}  // namespace hapsim::web
