// One browser's console connection, as protocol: the hello and its token,
// the class view (WatchClass, shared by ClassWatchHub), the one open
// trainee view (Subscribe, with the browser's acks) and unary calls (pause, resume, reset, push
// scenario, trials, sessions, scenes), each made on the server's own gRPC
// services over the in-process channel with the browser's token. The view
// reads its next frame only once the browser has been sent the previous
// one, so a stalled tab holds one frame here and the server's viewer link
// coalesces the rest (newest state wins); statuses wait one at a time.
#pragma once
#include <grpcpp/grpcpp.h>

#include <condition_variable>
#include <cstdint>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <string_view>

#include "console_transport.h"
#include "hapsim/classroom/access_policy.h"
#include "hapsim/v1/console.pb.h"
#include "hapsim/v1/session.grpc.pb.h"
#include "hapsim/v1/viewer.grpc.pb.h"
#include "hapsim/web/web_console.h"

namespace hapsim::web {

// Counts the gRPC calls the console's connections have open, so the
// endpoint can wait for all of them before the gRPC server stops.
class OpenCalls {
 public:
  void Add();
  void Remove();
  // False if calls were still open after `timeout`.
  bool WaitForNone(std::chrono::milliseconds timeout);

 private:
  std::mutex mutex_;
  std::condition_variable none_;
  int open_ = 0;
};

class ClassWatchHub;

struct ConsoleServices {
  std::shared_ptr<grpc::Channel> channel;
  ClassWatchHub* class_watches = nullptr;         // the class views, shared between connections
  const service::AccessPolicy* policy = nullptr;  // nullptr or disabled: development mode
  std::string server_version;
  OpenCalls* open_calls = nullptr;
};

class TraineeView;

class ConsoleSession : public std::enable_shared_from_this<ConsoleSession> {
 public:
  static constexpr int kMaxCallsInFlight = 8;

  ConsoleSession(const ConsoleServices& services, std::shared_ptr<ConsoleTransport> transport);
  ~ConsoleSession();

  // One binary message from the browser (I/O thread).
  void OnMessage(std::string_view bytes);
  // The connection is gone: ends the streams and forgets the transport.
  void OnClosed();

  // For the streams and calls (any thread): send an event; on_sent as
  // ConsoleTransport::Send's (false at once if the connection has closed).
  void SendEvent(const hapsim::v1::ConsoleEvent& event, std::function<void(bool sent)> on_sent);
  // A class status (an encoded ConsoleEvent), newest wins: while the
  // browser has not acknowledged the previous one, a newer one replaces the
  // one waiting.
  void OfferStatus(std::shared_ptr<const std::string> event_bytes);
  // Tells the browser its class view or trainee view ended, and why.
  void StreamEnded(const char* stream, const grpc::Status& status);
  // `view`'s stream ended: told unless the browser closed or replaced it.
  void ViewEnded(const grpc::Status& status, const TraineeView* view);
  void CallDone() { calls_in_flight_.fetch_sub(1); }
  // Sets the browser's token on a call's context.
  void Authorize(grpc::ClientContext* context) const;
  const ConsoleServices& services() const { return services_; }
  hapsim::v1::SessionService::Stub& sessions() { return *sessions_stub_; }
  hapsim::v1::ViewerService::Stub& viewers() { return *viewer_stub_; }

 private:
  void Hello(const hapsim::v1::ConsoleHello& hello);
  void WatchClass(const hapsim::v1::WatchClassRequest& request);
  void OpenView(const hapsim::v1::SubscribeRequest& request);
  void CloseView();
  void Ack(const hapsim::v1::ViewerAck& ack);
  void Call(const hapsim::v1::ConsoleCall& call);
  // Refuses the connection: tells the browser why, then closes.
  void Refuse(grpc::StatusCode code, const std::string& message);
  void StatusDone();  // the browser acknowledged the status, or it could not be sent

  ConsoleServices services_;
  std::unique_ptr<hapsim::v1::SessionService::Stub> sessions_stub_;
  std::unique_ptr<hapsim::v1::ViewerService::Stub> viewer_stub_;
  std::optional<std::string> token_;  // set by the hello ("" in development mode)
  bool refused_ = false;              // I/O thread only
  std::atomic<int> calls_in_flight_{0};
  // The transport and the streams, which gRPC threads also reach; recursive:
  // cancelling a stream may run its end (StreamEnded) inline.
  mutable std::recursive_mutex mutex_;
  std::shared_ptr<ConsoleTransport> transport_;
  TraineeView* view_ = nullptr;
  bool status_in_flight_ = false;
  std::shared_ptr<const std::string> next_status_;  // the newest status, waiting
};

}  // namespace hapsim::web
