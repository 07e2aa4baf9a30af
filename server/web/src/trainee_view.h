// The trainee view of one console connection: a Subscribe stream on the
// server's ViewerService with the browser's token. It reads a frame, hands
// it to the browser, and reads the next only once the browser has been
// sent it; the browser's acks go back on the stream, so the server's viewer
// link keeps the backlog to its ack window and sends the newest state.
// The ack's held time is measured here, from the frame leaving the server's
// stream to the browser's ack: everything past the in-process channel —
// socket buffers, a slow tab's message queue — counts as the viewer's, not
// as network, so at most ack_window frames are ever on their way to a
// browser (a far browser needs a larger window for the full rate). A
// hold keeps the reactor alive until it is cancelled or its stream ends,
// so the session may reach it (cancel, acks) at any time before that. It
// is created, started and cancelled on the I/O thread only.
#pragma once
#include <grpcpp/grpcpp.h>

#include <array>
#include <cstdint>
#include <memory>
#include <mutex>
#include <optional>

#include "console_session.h"

namespace hapsim::web {

class TraineeView final : public grpc::ClientBidiReactor<hapsim::v1::ViewerMessage, hapsim::v1::Frame> {
 public:
  explicit TraineeView(std::shared_ptr<ConsoleSession> owner) : owner_(std::move(owner)) {}
  void Start(const hapsim::v1::SubscribeRequest& request);
  // The browser closed or replaced this view, or left: end the call.
  void Cancel();
  // The browser's newest ack; acks are cumulative, so one waiting is enough.
  void Ack(const hapsim::v1::ViewerAck& ack);

  void OnReadDone(bool ok) override;
  void OnWriteDone(bool ok) override;
  void OnDone(const grpc::Status& status) override;

 private:
  void ReleaseHold();
  void WriteAckLocked();  // mutex_ held

  std::shared_ptr<ConsoleSession> owner_;
  grpc::ClientContext context_;
  hapsim::v1::Frame incoming_;
  hapsim::v1::ViewerMessage outgoing_;
  static constexpr std::size_t kFramesRemembered = 128;
  std::mutex mutex_;                                       // the fields below
  std::array<std::int64_t, kFramesRemembered> read_ns_{};  // when frame seq was read, at seq % 128
  std::uint64_t frames_read_ = 0;
  bool released_ = false;
  bool write_busy_ = false;
  std::optional<hapsim::v1::ViewerAck> pending_ack_;
};

}  // namespace hapsim::web
