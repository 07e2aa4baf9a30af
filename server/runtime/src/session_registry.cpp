#include "hapsim/runtime/session_registry.h"

#include <spdlog/spdlog.h>

#include <new>
#include <stdexcept>

#include "hapsim/common/clock.h"
#include "hapsim/common/session_id.h"
#include "hapsim/runtime/scene_builder.h"

namespace hapsim::service {

SessionRegistry::SessionRegistry(SessionDefaults defaults, TickPool* pool, SessionTransport* transport,
                                 SessionListener* listener, TickListenerFactory tick_listeners)
    : defaults_(defaults),
      pool_(pool),
      transport_(transport),
      listener_(listener),
      tick_listeners_(std::move(tick_listeners)) {}

SessionRegistry::~SessionRegistry() { CloseAll(); }

void SessionRegistry::ReleaseReservation(const std::string& id) {
  std::lock_guard lock(mutex_);
  reserved_.erase(id);
}

void SessionRegistry::PublishTableLocked() {
  table_.Store(std::make_shared<const SessionTable>(sessions_));
}

std::shared_ptr<Session> SessionRegistry::Create(std::string id, std::string scene, std::string owner,
                                                 std::map<std::string, double> params) {
  return CreateSeeded(std::move(id), std::move(scene), std::move(owner), std::move(params), {});
}

std::shared_ptr<Session> SessionRegistry::CreateSeeded(std::string id, std::string scene, std::string owner,
                                                       std::map<std::string, double> params, SessionSeed seed) {
  id = Reserve(std::move(id), owner);
  std::shared_ptr<Session> session;
  const std::string scene_name = scene.empty() ? "tissue_block" : scene;
  try {  // no lock held: other sessions keep ticking and routing poses
    session = Build(id, std::move(scene), std::move(owner), std::move(params), std::move(seed));
  } catch (const std::invalid_argument& e) {  // scenes throw invalid_argument on bad parameters
    ReleaseReservation(id);
    throw ServiceError(ErrorCode::kInvalidArgument, e.what());
  } catch (const std::bad_alloc&) {  // a mesh within the limits, but this machine is out of memory
    ReleaseReservation(id);
    throw ServiceError(ErrorCode::kResourceExhausted, "not enough memory to build scene '" + scene_name.substr(0, 80) + "'");
  } catch (...) {  // e.g. the DDS endpoints could not be created: not the caller's fault
    ReleaseReservation(id);
    throw;
  }
  Publish(id, session);  // then start ticking
  session->port().StartReceiving(session.get());
  pool_->Add(session.get(), common::SteadyNowNs());
  spdlog::info("session '{}' created: scene {}", id, session->config().scene);
  return session;
}

std::string SessionRegistry::Reserve(std::string id, const std::string& owner) {
  std::lock_guard lock(mutex_);
  if (id.empty()) {
    do {
      id = "session-" + std::to_string(next_generated_id_++);
    } while (sessions_.count(id) || reserved_.count(id));
  }
  if (!common::IsValidSessionId(id)) {
    throw ServiceError(ErrorCode::kInvalidArgument,
                       "session id '" + id.substr(0, 80) + "' is invalid: use 1-63 characters of A-Z a-z 0-9 _ -");
  }
  if (sessions_.count(id) || reserved_.count(id)) {
    throw ServiceError(ErrorCode::kAlreadyExists, "session '" + id + "' already exists");
  }
  if (sessions_.size() + reserved_.size() >= defaults_.max_sessions) {
    throw ServiceError(ErrorCode::kResourceExhausted,
                       "this server already runs its maximum of " + std::to_string(defaults_.max_sessions) +
                           " sessions; close one or start the server with a larger --max-sessions");
  }
  if (owner.size() > 256) throw ServiceError(ErrorCode::kInvalidArgument, "owner name longer than 256 characters");
  reserved_.insert(id);
  return id;
}

std::shared_ptr<Session> SessionRegistry::Build(const std::string& id, std::string scene, std::string owner,
                                                std::map<std::string, double> params, SessionSeed seed) {
  std::shared_ptr<Session> session;
  SessionConfig config;
  config.id = id;
  config.scene = scene.empty() ? "tissue_block" : std::move(scene);
  config.owner = std::move(owner);
  config.params = std::move(params);
  config.tick_period_s = defaults_.tick_period_s;
  config.frame_rate_hz = defaults_.frame_rate_hz;
  config.pose_timeout_s = defaults_.pose_timeout_s;
  config.pose_slack_s = defaults_.pose_slack_s;
  config.pose_extrapolation_s = defaults_.pose_extrapolation_s;
  config.model_deadband = defaults_.model_deadband;
  config.first_tick = seed.first_tick;
  config.start_paused = seed.paused;
  if (seed.tick_period_s > 0.0) config.tick_period_s = seed.tick_period_s;
  config.step_s = seed.step_s;
  // The scene and the session's first-touched buffers, at low priority;
  // the DDS endpoints only once the scene built (a failed build leaves no
  // writer in the session's partition for another server to see).
  RunAtLowPriority([&] {
    auto built = seed.scene ? std::move(seed.scene) : core::MakeScene({config.scene, config.params});
    auto port = transport_->Open(config.id);
    auto tick_listener = seed.listener ? seed.listener : tick_listeners_ ? tick_listeners_(config) : nullptr;
    session = std::make_shared<Session>(std::move(config), std::move(built), std::move(port), std::move(tick_listener),
                                        std::move(seed.source));
  });
  return session;
}

void SessionRegistry::Publish(const std::string& id, const std::shared_ptr<Session>& session) {
  std::lock_guard lock(mutex_);
  reserved_.erase(id);
  sessions_.emplace(id, session);
  PublishTableLocked();
}

std::shared_ptr<Session> SessionRegistry::Find(std::string_view id) const {
  const auto table = Table();
  const auto it = table->find(id);
  return it == table->end() ? nullptr : it->second;
}

std::shared_ptr<Session> SessionRegistry::FindOrThrow(std::string_view id) const {
  auto s = Find(id);
  if (!s) throw ServiceError(ErrorCode::kNotFound, "no session '" + std::string(id.substr(0, 80)) + "'");
  return s;
}

void SessionRegistry::Shut(Session& s, CloseReason why) {
  s.port().StopReceiving();
  pool_->Remove(&s);  // waits for a running tick; no tick after this
  if (listener_) listener_->OnSessionClosed(s, why);
}

void SessionRegistry::Close(std::string_view id) {
  std::shared_ptr<Session> s;
  {
    std::lock_guard lock(mutex_);
    const auto it = sessions_.find(id);
    if (it == sessions_.end()) throw ServiceError(ErrorCode::kNotFound, "no session '" + std::string(id.substr(0, 80)) + "'");
    s = it->second;
    sessions_.erase(it);
    PublishTableLocked();
  }
  Shut(*s, CloseReason::kClosed);
  spdlog::info("session '{}' closed after {} ticks", s->id(), s->counters().tick.ticks.load());
}

void SessionRegistry::CloseAll() {
  SessionTable all;
  {
    std::lock_guard lock(mutex_);
    all.swap(sessions_);
    PublishTableLocked();
  }
  for (auto& [id, s] : all) Shut(*s, CloseReason::kServerStopping);
}

std::vector<std::shared_ptr<Session>> SessionRegistry::List() const {
  const auto table = Table();
  std::vector<std::shared_ptr<Session>> out;
  out.reserve(table->size());
  for (const auto& [id, s] : *table) out.push_back(s);
  return out;
}

}  // namespace hapsim::service
