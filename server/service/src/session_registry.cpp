#include "hapsim/service/session_registry.h"

#include <spdlog/spdlog.h>

#include "hapsim/service/viewer_link.h"

namespace hapsim::service {

bool IsValidSessionId(std::string_view id) {
  if (id.empty() || id.size() > 63) return false;
  for (const char c : id) {
    const bool ok = (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9') || c == '_' || c == '-';
    if (!ok) return false;
  }
  return true;
}

SessionRegistry::SessionRegistry(SessionDefaults defaults, std::function<void()> wake_dds)
    : defaults_(defaults), wake_dds_(std::move(wake_dds)) {}

SessionRegistry::~SessionRegistry() { CloseAll(); }

std::shared_ptr<Session> SessionRegistry::Create(std::string id, std::string scene, std::string owner,
                                                 std::map<std::string, double> params) {
  std::lock_guard lock(mutex_);
  if (id.empty()) {
    do {
      id = "session-" + std::to_string(next_generated_id_++);
    } while (sessions_.count(id));
  }
  if (!IsValidSessionId(id)) {
    throw ServiceError(ErrorCode::kInvalidArgument,
                       "session id '" + id.substr(0, 80) + "' is invalid: use 1-63 characters of A-Z a-z 0-9 _ -");
  }
  if (sessions_.count(id)) throw ServiceError(ErrorCode::kAlreadyExists, "session '" + id + "' already exists");
  if (sessions_.size() >= defaults_.max_sessions) {
    throw ServiceError(ErrorCode::kResourceExhausted,
                       "this server already runs its maximum of " + std::to_string(defaults_.max_sessions) +
                           " sessions; close one or start the server with a larger --max-sessions");
  }
  if (owner.size() > 256) throw ServiceError(ErrorCode::kInvalidArgument, "owner name longer than 256 characters");
  SessionConfig config;
  config.id = id;
  config.scene = scene.empty() ? "tissue_block" : std::move(scene);
  config.owner = std::move(owner);
  config.params = std::move(params);
  config.tick_period_s = defaults_.tick_period_s;
  config.frame_rate_hz = defaults_.frame_rate_hz;
  config.pose_timeout_s = defaults_.pose_timeout_s;
  std::shared_ptr<Session> session;
  try {
    session = std::make_shared<Session>(std::move(config), wake_dds_);
  } catch (const std::exception& e) {  // scenes throw invalid_argument on bad parameters
    throw ServiceError(ErrorCode::kInvalidArgument, e.what());
  }
  session->Start();
  sessions_.emplace(id, session);
  spdlog::info("session '{}' created: scene {}", id, session->config().scene);
  return session;
}

std::shared_ptr<Session> SessionRegistry::Find(std::string_view id) const {
  std::lock_guard lock(mutex_);
  const auto it = sessions_.find(id);
  return it == sessions_.end() ? nullptr : it->second;
}

std::shared_ptr<Session> SessionRegistry::FindOrThrow(std::string_view id) const {
  auto s = Find(id);
  if (!s) throw ServiceError(ErrorCode::kNotFound, "no session '" + std::string(id.substr(0, 80)) + "'");
  return s;
}

namespace {
void Shut(Session& s, const grpc::Status& why) {
  s.Stop();
  for (const auto& v : s.Viewers()) v->Close(why);
}
}  // namespace

void SessionRegistry::Close(std::string_view id) {
  std::shared_ptr<Session> s;
  {
    std::lock_guard lock(mutex_);
    const auto it = sessions_.find(id);
    if (it == sessions_.end()) throw ServiceError(ErrorCode::kNotFound, "no session '" + std::string(id.substr(0, 80)) + "'");
    s = it->second;
    sessions_.erase(it);
  }
  Shut(*s, grpc::Status(grpc::StatusCode::NOT_FOUND, "session '" + s->id() + "' was closed"));
  spdlog::info("session '{}' closed after {} ticks", s->id(), s->counters().ticks.load());
}

void SessionRegistry::CloseAll() {
  std::map<std::string, std::shared_ptr<Session>, std::less<>> all;
  {
    std::lock_guard lock(mutex_);
    all.swap(sessions_);
  }
  for (auto& [id, s] : all) Shut(*s, grpc::Status(grpc::StatusCode::UNAVAILABLE, "server shutting down"));
}

std::vector<std::shared_ptr<Session>> SessionRegistry::List() const {
  std::lock_guard lock(mutex_);
  std::vector<std::shared_ptr<Session>> out;
  out.reserve(sessions_.size());
  for (const auto& [id, s] : sessions_) out.push_back(s);
  return out;
}

}  // namespace hapsim::service
