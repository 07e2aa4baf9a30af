#include "console_session.h"

#include <spdlog/spdlog.h>

#include <utility>

#include "class_watch_hub.h"
#include "hapsim/runtime/errors.h"
#include "trainee_view.h"

namespace hapsim::web {

namespace v1 = hapsim::v1;

void OpenCalls::Add() {
  std::lock_guard lock(mutex_);
  ++open_;
}

void OpenCalls::Remove() {
  std::lock_guard lock(mutex_);
  if (--open_ == 0) none_.notify_all();
}

bool OpenCalls::WaitForNone(std::chrono::milliseconds timeout) {
  std::unique_lock lock(mutex_);
  return none_.wait_for(lock, timeout, [this] { return open_ == 0; });
}

namespace {

// A unary SessionService call made for the browser: context, request and
// response live until the answer has been handed to the browser.
template <class Request, class Response>
struct PendingCall {
  grpc::ClientContext context;
  Request request;
  Response response;
};

// Starts `invoke` (one async SessionService method) and answers the browser
// with a ConsoleReply of the same id; `place` puts the response into it.
template <class Request, class Response, class Invoke, class Place>
void StartUnaryCall(const std::shared_ptr<ConsoleSession>& owner, std::uint32_t id, const Request& request,
                    Invoke invoke, Place place) {
  auto call = std::make_shared<PendingCall<Request, Response>>();
  call->request = request;
  owner->Authorize(&call->context);
  owner->services().open_calls->Add();
  invoke(owner->sessions().async(), &call->context, &call->request, &call->response,
         [owner, call, id, place](grpc::Status status) {
           v1::ConsoleEvent event;
           v1::ConsoleReply* reply = event.mutable_reply();
           reply->set_id(id);
           reply->set_code(status.error_code());
           if (status.ok()) {
             place(reply, &call->response);
           } else {
             reply->set_message(status.error_message());
           }
           OpenCalls* calls = owner->services().open_calls;
           owner->CallDone();
           owner->SendEvent(event, [](bool) {});
           calls->Remove();
         });
}

using AsyncSessions = v1::SessionService::Stub::async_interface;
using Done = std::function<void(grpc::Status)>;

}  // namespace

ConsoleSession::ConsoleSession(const ConsoleServices& services, std::shared_ptr<ConsoleTransport> transport)
    : services_(services),
      sessions_stub_(v1::SessionService::NewStub(services.channel)),
      viewer_stub_(v1::ViewerService::NewStub(services.channel)),
      transport_(std::move(transport)) {}

ConsoleSession::~ConsoleSession() = default;

void ConsoleSession::OnMessage(std::string_view bytes) {
  if (refused_) return;
  v1::ConsoleRequest request;
  if (!request.ParseFromArray(bytes.data(), static_cast<int>(bytes.size()))) {
    Refuse(grpc::StatusCode::INVALID_ARGUMENT, "not a hapsim.v1.ConsoleRequest");
    return;
  }
  if (!token_) {
    if (request.request_case() != v1::ConsoleRequest::kHello) {
      Refuse(grpc::StatusCode::UNAUTHENTICATED, "the first message must be a hello with the class token");
      return;
    }
    Hello(request.hello());
    return;
  }
  switch (request.request_case()) {
    case v1::ConsoleRequest::kWatchClass:
      WatchClass(request.watch_class());
      break;
    case v1::ConsoleRequest::kOpenView:
      OpenView(request.open_view());
      break;
    case v1::ConsoleRequest::kAck:
      Ack(request.ack());
      break;
    case v1::ConsoleRequest::kCall:
      Call(request.call());
      break;
    case v1::ConsoleRequest::kCloseView:
      CloseView();
      break;
    case v1::ConsoleRequest::kStatusAck:
      StatusDone();
      break;
    case v1::ConsoleRequest::kHello:
      Refuse(grpc::StatusCode::INVALID_ARGUMENT, "hello sent twice");
      break;
    case v1::ConsoleRequest::REQUEST_NOT_SET:
      Refuse(grpc::StatusCode::INVALID_ARGUMENT, "empty request");
      break;
  }
}

void ConsoleSession::Hello(const v1::ConsoleHello& hello) {
  v1::ConsoleEvent event;
  v1::ConsoleWelcome* welcome = event.mutable_welcome();
  welcome->set_server(services_.server_version);
  if (!services_.policy || !services_.policy->enabled()) {
    token_ = "";  // development mode: no token, none forwarded (whatever the page sent)
    SendEvent(event, [](bool) {});
    return;
  }
  const std::string authorization = "Bearer " + hello.token();
  try {
    const auto who = services_.policy->Authenticate(&authorization);
    welcome->set_name(who->name);
    welcome->set_role(service::RoleName(who->role));
    welcome->set_class_name(who->class_name);
    for (const auto& s : who->sessions) welcome->add_sessions(s);
  } catch (const service::ServiceError& e) {
    Refuse(grpc::StatusCode::UNAUTHENTICATED, e.what());  // counted by Authenticate
    return;
  }
  token_ = hello.token();  // a known token: forwarded on every call
  SendEvent(event, [](bool) {});
}

void ConsoleSession::Authorize(grpc::ClientContext* context) const {
  if (token_ && !token_->empty()) context->AddMetadata("authorization", "Bearer " + *token_);
}

void ConsoleSession::WatchClass(const v1::WatchClassRequest& request) {
  services_.class_watches->Join(*token_, request, shared_from_this());
}

void ConsoleSession::OpenView(const v1::SubscribeRequest& request) {
  auto* view = new TraineeView(shared_from_this());
  {
    std::lock_guard lock(mutex_);
    if (!transport_) {
      delete view;
      return;
    }
    if (TraineeView* old = std::exchange(view_, view)) old->Cancel();
  }
  view->Start(request);
}

void ConsoleSession::CloseView() {
  std::lock_guard lock(mutex_);
  if (TraineeView* old = std::exchange(view_, nullptr)) old->Cancel();
}

void ConsoleSession::Ack(const v1::ViewerAck& ack) {
  std::lock_guard lock(mutex_);
  if (view_) view_->Ack(ack);
}

void ConsoleSession::Call(const v1::ConsoleCall& call) {
  if (calls_in_flight_.fetch_add(1) >= kMaxCallsInFlight) {
    calls_in_flight_.fetch_sub(1);
    Refuse(grpc::StatusCode::RESOURCE_EXHAUSTED,
           "more than " + std::to_string(kMaxCallsInFlight) + " calls waiting for their answers");
    return;
  }
  const auto self = shared_from_this();
  const std::uint32_t id = call.id();
  using v1::ConsoleReply;
  auto session_info = [](ConsoleReply* out, v1::SessionInfo* r) { out->mutable_session()->Swap(r); };
  switch (call.call_case()) {
    case v1::ConsoleCall::kPauseSession:
      StartUnaryCall<v1::SessionRef, v1::SessionInfo>(
          self, id, call.pause_session(),
          [](AsyncSessions* a, auto* c, auto* q, auto* r, Done d) { a->PauseSession(c, q, r, std::move(d)); },
          session_info);
      break;
    case v1::ConsoleCall::kResumeSession:
      StartUnaryCall<v1::SessionRef, v1::SessionInfo>(
          self, id, call.resume_session(),
          [](AsyncSessions* a, auto* c, auto* q, auto* r, Done d) { a->ResumeSession(c, q, r, std::move(d)); },
          session_info);
      break;
    case v1::ConsoleCall::kResetSession:
      StartUnaryCall<v1::SessionRef, v1::SessionInfo>(
          self, id, call.reset_session(),
          [](AsyncSessions* a, auto* c, auto* q, auto* r, Done d) { a->ResetSession(c, q, r, std::move(d)); },
          session_info);
      break;
    case v1::ConsoleCall::kPushScenario:
      StartUnaryCall<v1::PushScenarioRequest, v1::PushScenarioResponse>(
          self, id, call.push_scenario(),
          [](AsyncSessions* a, auto* c, auto* q, auto* r, Done d) { a->PushScenario(c, q, r, std::move(d)); },
          [](ConsoleReply* out, v1::PushScenarioResponse* r) { out->mutable_pushed()->Swap(r); });
      break;
    case v1::ConsoleCall::kGetTrials:
      StartUnaryCall<v1::TrialQuery, v1::TrialReport>(
          self, id, call.get_trials(),
          [](AsyncSessions* a, auto* c, auto* q, auto* r, Done d) { a->GetTrials(c, q, r, std::move(d)); },
          [](ConsoleReply* out, v1::TrialReport* r) { out->mutable_trials()->Swap(r); });
      break;
    case v1::ConsoleCall::kListSessions:
      StartUnaryCall<v1::ListSessionsRequest, v1::ListSessionsResponse>(
          self, id, call.list_sessions(),
          [](AsyncSessions* a, auto* c, auto* q, auto* r, Done d) { a->ListSessions(c, q, r, std::move(d)); },
          [](ConsoleReply* out, v1::ListSessionsResponse* r) { out->mutable_sessions()->Swap(r); });
      break;
    case v1::ConsoleCall::kListScenes:
      StartUnaryCall<v1::ListScenesRequest, v1::ListScenesResponse>(
          self, id, call.list_scenes(),
          [](AsyncSessions* a, auto* c, auto* q, auto* r, Done d) { a->ListScenes(c, q, r, std::move(d)); },
          [](ConsoleReply* out, v1::ListScenesResponse* r) { out->mutable_scenes()->Swap(r); });
      break;
    case v1::ConsoleCall::CALL_NOT_SET:
      calls_in_flight_.fetch_sub(1);
      Refuse(grpc::StatusCode::INVALID_ARGUMENT, "a call names no method");
      break;
  }
}

// Sends are handed to the transport under the lock (Send only queues), so
// none can slip in after a refusal or a close has taken the transport.
void ConsoleSession::SendEvent(const v1::ConsoleEvent& event, std::function<void(bool sent)> on_sent) {
  auto bytes = std::make_shared<std::string>();
  event.SerializeToString(bytes.get());
  {
    std::lock_guard lock(mutex_);
    if (transport_) {
      transport_->Send(std::move(bytes), std::move(on_sent));
      return;
    }
  }
  on_sent(false);
}

void ConsoleSession::OfferStatus(std::shared_ptr<const std::string> event_bytes) {
  std::lock_guard lock(mutex_);
  if (!transport_) return;
  if (status_in_flight_) {
    next_status_ = std::move(event_bytes);
    return;
  }
  status_in_flight_ = true;
  transport_->Send(std::move(event_bytes), [self = weak_from_this()](bool sent) {
    if (!sent) {
      if (auto session = self.lock()) session->StatusDone();
    }
  });
}

void ConsoleSession::StatusDone() {
  std::shared_ptr<const std::string> next;
  {
    std::lock_guard lock(mutex_);
    if (!status_in_flight_) return;  // an ack for nothing: ignored
    status_in_flight_ = false;
    next = std::move(next_status_);
  }
  if (next) OfferStatus(std::move(next));
}

void ConsoleSession::ViewEnded(const grpc::Status& status, const TraineeView* view) {
  {
    std::lock_guard lock(mutex_);
    if (view != view_) return;  // closed or replaced by the browser, or the connection is gone
    view_ = nullptr;
  }
  StreamEnded("view", status);
}

void ConsoleSession::StreamEnded(const char* stream, const grpc::Status& status) {
  v1::ConsoleEvent event;
  v1::ConsoleStreamEnded* ended = event.mutable_ended();
  ended->set_stream(stream);
  ended->set_code(status.error_code());
  ended->set_message(status.error_message());
  SendEvent(event, [](bool) {});
}

// A refusal is the last thing the browser hears: the session lets go of its
// transport first (as if the connection had closed), so a call's answer or
// a frame finishing on another thread afterwards is dropped, not sent.
void ConsoleSession::Refuse(grpc::StatusCode code, const std::string& message) {
  refused_ = true;
  spdlog::info("web console: connection refused: {}", message);
  v1::ConsoleEvent event;
  event.mutable_refused()->set_code(code);
  event.mutable_refused()->set_message(message);
  auto bytes = std::make_shared<std::string>(event.SerializeAsString());
  std::lock_guard lock(mutex_);
  const std::shared_ptr<ConsoleTransport> transport = transport_;
  OnClosed();
  // Weak: the transport keeps this callback until the refusal is written,
  // and a strong copy would keep the transport alive if that never happens
  // (the server stopping mid-write).
  if (transport) {
    transport->Send(std::move(bytes), [weak = std::weak_ptr<ConsoleTransport>(transport)](bool) {
      if (const auto t = weak.lock()) t->Close();
    });
  }
}

void ConsoleSession::OnClosed() {
  std::lock_guard lock(mutex_);
  transport_.reset();
  next_status_.reset();
  if (TraineeView* view = std::exchange(view_, nullptr)) view->Cancel();
  services_.class_watches->Leave(this);
}

}  // namespace hapsim::web
