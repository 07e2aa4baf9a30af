#include "class_watch_hub.h"

#include <vector>

#include "console_session.h"

namespace hapsim::web {

namespace v1 = hapsim::v1;

// One WatchClass stream on the server's services. A hold keeps it alive
// until it is cancelled (no browser watches it any more) or it ends, so the
// hub may cancel it at any time before that.
class ClassWatchHub::Watch final : public grpc::ClientReadReactor<v1::ClassStatus> {
 public:
  Watch(ClassWatchHub* hub, std::string key, const std::string& token, const v1::WatchClassRequest& request)
      : hub_(hub), key_(std::move(key)), request_(request) {
    hub_->open_calls_->Add();
    if (!token.empty()) context_.AddMetadata("authorization", "Bearer " + token);
    hub_->stub_->async()->WatchClass(&context_, &request_, this);
    AddHold();
    StartRead(&incoming_);
    StartCall();
  }
  const std::string& key() const { return key_; }

  // Called with the hub's lock held, so the stream has not ended yet (its
  // end takes the lock before it deletes the reactor). The hold is released
  // last: the end may run inline from there.
  void Cancel() {
    const bool holding = !released_.exchange(true);
    context_.TryCancel();
    if (holding) RemoveHold();
  }

  void OnReadDone(bool ok) override {
    if (!ok) {
      ReleaseHold();
      return;
    }
    hub_->Deliver(this, incoming_);
    StartRead(&incoming_);
  }

  void OnDone(const grpc::Status& status) override {
    ClassWatchHub* hub = hub_;
    hub->Ended(this, status);
    delete this;
    hub->open_calls_->Remove();
  }

 private:
  void ReleaseHold() {
    if (released_.exchange(true)) return;
    RemoveHold();  // may run OnDone (and delete this) inline: the last thing touched
  }

  ClassWatchHub* hub_;
  std::string key_;
  grpc::ClientContext context_;
  v1::WatchClassRequest request_;
  v1::ClassStatus incoming_;
  std::atomic<bool> released_{false};
};

ClassWatchHub::ClassWatchHub(std::shared_ptr<grpc::Channel> channel, OpenCalls* open_calls)
    : stub_(v1::SessionService::NewStub(channel)), open_calls_(open_calls) {}

ClassWatchHub::~ClassWatchHub() = default;

void ClassWatchHub::Join(const std::string& token, const v1::WatchClassRequest& request,
                         const std::shared_ptr<ConsoleSession>& who) {
  // The token is part of the key: a stream is authorised for its caller only.
  const std::string key = token + '\n' + request.class_name() + '\n' + std::to_string(request.rate_hz());
  std::lock_guard lock(mutex_);
  Watch* to_cancel = nullptr;
  LeaveLocked(who.get(), &to_cancel);
  const auto found = by_key_.find(key);
  Watch* watch = found != by_key_.end() ? found->second : nullptr;
  if (!watch) {
    watch = new Watch(this, key, token, request);
    by_key_[key] = watch;
  }
  members_[who.get()] = {watch, who};
  if (to_cancel && to_cancel != watch) to_cancel->Cancel();
}

void ClassWatchHub::Leave(const ConsoleSession* who) {
  std::lock_guard lock(mutex_);
  Watch* to_cancel = nullptr;
  LeaveLocked(who, &to_cancel);
  if (to_cancel) to_cancel->Cancel();
}

void ClassWatchHub::LeaveLocked(const ConsoleSession* who, Watch** to_cancel) {
  const auto member = members_.find(who);
  if (member == members_.end()) return;
  Watch* watch = member->second.first;
  members_.erase(member);
  for (const auto& [other, entry] : members_) {
    if (entry.first == watch) return;  // others still watch it
  }
  const auto live = by_key_.find(watch->key());
  if (live != by_key_.end() && live->second == watch) by_key_.erase(live);
  *to_cancel = watch;  // cancelled by the caller, still under the lock
}

void ClassWatchHub::Deliver(Watch* watch, const v1::ClassStatus& status) {
  v1::ConsoleEvent event;
  *event.mutable_class_status() = status;
  auto bytes = std::make_shared<const std::string>(event.SerializeAsString());
  std::vector<std::shared_ptr<ConsoleSession>> watchers;
  {
    std::lock_guard lock(mutex_);
    for (const auto& [who, entry] : members_) {
      if (entry.first != watch) continue;
      if (auto session = entry.second.lock()) watchers.push_back(std::move(session));
    }
  }
  for (const auto& session : watchers) session->OfferStatus(bytes);
}

void ClassWatchHub::Ended(Watch* watch, const grpc::Status& status) {
  std::vector<std::shared_ptr<ConsoleSession>> watchers;
  {
    std::lock_guard lock(mutex_);
    const auto live = by_key_.find(watch->key());
    if (live != by_key_.end() && live->second == watch) by_key_.erase(live);
    for (auto it = members_.begin(); it != members_.end();) {
      if (it->second.first == watch) {
        if (auto session = it->second.second.lock()) watchers.push_back(std::move(session));
        it = members_.erase(it);
      } else {
        ++it;
      }
    }
  }
  for (const auto& session : watchers) session->StreamEnded("class", status);
}

}  // namespace hapsim::web
