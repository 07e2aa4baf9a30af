#include "hapsim/service/session_service.h"

#include <spdlog/spdlog.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>

#include "hapsim/core/assessment/scoring.h"
#include "hapsim/core/scenes/scene.h"
#include "hapsim/dds/partition.h"
#include "hapsim/service/class_status.h"

namespace hapsim::service {

using grpc::Status;
using grpc::StatusCode;

Status ToGrpcStatus(const ServiceError& e) {
  switch (e.code()) {
    case ErrorCode::kInvalidArgument: return {StatusCode::INVALID_ARGUMENT, e.what()};
    case ErrorCode::kNotFound: return {StatusCode::NOT_FOUND, e.what()};
    case ErrorCode::kAlreadyExists: return {StatusCode::ALREADY_EXISTS, e.what()};
    case ErrorCode::kResourceExhausted: return {StatusCode::RESOURCE_EXHAUSTED, e.what()};
    case ErrorCode::kFailedPrecondition: return {StatusCode::FAILED_PRECONDITION, e.what()};
    case ErrorCode::kUnauthenticated: return {StatusCode::UNAUTHENTICATED, e.what()};
    case ErrorCode::kPermissionDenied: return {StatusCode::PERMISSION_DENIED, e.what()};
  }
  return {StatusCode::INTERNAL, e.what()};
}

namespace {

// Runs a handler body, turning bad input into a status: a client's mistake
// never escapes as an exception.
template <class F>
Status Guarded(const char* rpc, F&& body) {
  try {
    body();
    return Status::OK;
  } catch (const ServiceError& e) {
    return ToGrpcStatus(e);
  } catch (const std::exception& e) {
    spdlog::error("{} failed: {}", rpc, e.what());
    return {StatusCode::INTERNAL, std::string(rpc) + " failed: " + e.what()};
  }
}

const AccessPolicy& OpenPolicy() {
  static const AccessPolicy open;
  return open;
}

}  // namespace

std::optional<Principal> AuthenticateCall(const AccessPolicy& policy, const grpc::ServerContextBase* context) {
  if (!policy.enabled()) return std::nullopt;
  if (!context) return policy.Authenticate(nullptr);
  const auto& metadata = context->client_metadata();
  const auto found = metadata.find("authorization");
  if (found == metadata.end()) return policy.Authenticate(nullptr);
  const std::string value(found->second.data(), found->second.size());
  return policy.Authenticate(&value);
}

SessionServiceImpl::SessionServiceImpl(SessionRegistry* registry, const ViewerHub* hub, ScoreBook* scores,
                                       const AccessPolicy* policy, std::uint32_t dds_domain, const TrialBook* trials)
    : registry_(registry), hub_(hub), scores_(scores), policy_(policy ? policy : &OpenPolicy()),
      dds_domain_(dds_domain), trials_(trials) {}

std::optional<Principal> SessionServiceImpl::Caller(const grpc::ServerContext* context) const {
  return AuthenticateCall(*policy_, context);
}

void DescribeSession(const Session& s, hapsim::v1::SessionInfo* info) {
  const auto& c = s.counters();
  info->set_session_id(s.id());
  info->set_scene(s.config().scene);
  info->set_owner(s.config().owner);
  info->set_paused(s.paused());
  info->set_sim_time_s(c.sim_time_s.load());
  info->set_ticks(c.ticks.load());
  info->set_late_ticks(c.late_ticks.load());
  info->set_device_clocked_ticks(c.device_clocked_ticks.load());
  info->set_poses_from_other_devices(c.poses_from_other_devices.load());
  info->set_poses_stale(c.poses_stale.load());
  info->set_viewer_frames_coalesced(c.viewer_frames_coalesced.load());
  info->set_poses_wrong_session(c.poses_wrong_session.load());
  info->set_owning_device_id(c.owning_device_id.load());
  info->set_device_streaming(c.device_streaming.load());
  info->set_max_tick_lateness_s(static_cast<double>(c.max_lateness_ns.load()) * 1e-9);
  info->set_viewers(c.viewers.load());
  info->set_poses_received(c.poses_received.load());
  info->set_poses_rejected(c.poses_rejected.load());
  info->set_force_models_sent(c.force_models_sent.load());
  info->set_numerical_resets(c.numerical_resets.load());
  info->set_tick_period_s(s.config().tick_period_s);
  info->set_peak_tool_force_n(c.peak_tool_force_N.load());
}

Status SessionServiceImpl::ListScenes(grpc::ServerContext* context, const hapsim::v1::ListScenesRequest*,
                                      hapsim::v1::ListScenesResponse* out) {
  const Status allowed = Guarded("ListScenes", [&] { policy_->Authorize(Caller(context), Action::kListScenes, ""); });
  if (!allowed.ok()) return allowed;
  for (const auto& scene : core::SceneCatalog()) {
    auto* s = out->add_scenes();
    s->set_name(scene.name);
    s->set_description(scene.description);
    for (const auto& p : scene.params) {
      auto* q = s->add_parameters();
      q->set_name(p.spec.name);
      q->set_unit(p.spec.unit);
      q->set_default_value(p.default_value);
      q->set_min(p.spec.min);
      q->set_max(p.spec.max);
      q->set_min_exclusive(p.spec.min_open);
      q->set_max_exclusive(p.spec.max_open);
      q->set_integer(p.spec.integer);
      q->set_description(p.spec.description);
      for (const auto& c : p.spec.choices) q->add_choices(c);
      q->set_range(core::DescribeRange(p.spec));
    }
  }
  return Status::OK;
}

Status SessionServiceImpl::CreateSession(grpc::ServerContext* context, const hapsim::v1::CreateSessionRequest* req,
                                         hapsim::v1::SessionInfo* out) {
  std::shared_ptr<Session> created;
  const Status status = Guarded("CreateSession", [&] {
    const auto who = Caller(context);
    policy_->Authorize(who, Action::kCreateClose, req->session_id());
    Placement placement = PlacementOf(req->session_id());
    std::string owner = req->owner().empty() ? std::move(placement.trainee) : req->owner();
    if (req->params_size() > 64) throw ServiceError(ErrorCode::kInvalidArgument, "more than 64 scene parameters");
    std::map<std::string, double> params;
    for (const auto& [key, value] : req->params()) {
      if (!std::isfinite(value)) {
        throw ServiceError(ErrorCode::kInvalidArgument, "scene parameter '" + key.substr(0, 80) + "' is not finite");
      }
      params.emplace(key, value);
    }
    created = registry_->Create(req->session_id(), req->scene(), std::move(owner), std::move(params),
                                placement.targets);
  });
  if (!status.ok()) return status;
  // The build yields the CPU to ticks, so on a saturated server it can
  // outlast the client's deadline: a session nobody is told about must not
  // linger and count against --max-sessions.
  if (context && context->IsCancelled()) {
    try {
      registry_->Close(created->id());
    } catch (const ServiceError&) {  // closed meanwhile by someone else
    }
    return {StatusCode::CANCELLED, "the client gave up before session '" + created->id() + "' was built; it was closed again"};
  }
  DescribeSession(*created, out);
  return Status::OK;
}

Status SessionServiceImpl::ListSessions(grpc::ServerContext* context, const hapsim::v1::ListSessionsRequest*,
                                        hapsim::v1::ListSessionsResponse* out) {
  return Guarded("ListSessions", [&] {
    const auto who = Caller(context);
    policy_->Authorize(who, Action::kListSessions, "");
    for (const auto& s : registry_->List()) {
      if (policy_->Allows(who, Action::kView, s->id())) DescribeSession(*s, out->add_sessions());
    }
  });
}

Status SessionServiceImpl::GetSession(grpc::ServerContext* context, const hapsim::v1::SessionRef* req,
                                      hapsim::v1::SessionInfo* out) {
  return Guarded("GetSession", [&] {
    policy_->Authorize(Caller(context), Action::kView, req->session_id());
    DescribeSession(*registry_->FindOrThrow(req->session_id()), out);
  });
}

Status SessionServiceImpl::CloseSession(grpc::ServerContext* context, const hapsim::v1::SessionRef* req,
                                        hapsim::v1::CloseSessionResponse*) {
  return Guarded("CloseSession", [&] {
    policy_->Authorize(Caller(context), Action::kCreateClose, req->session_id());
    registry_->Close(req->session_id());
  });
}

Status SessionServiceImpl::PauseSession(grpc::ServerContext* context, const hapsim::v1::SessionRef* req,
                                        hapsim::v1::SessionInfo* out) {
  return Guarded("PauseSession", [&] {
    policy_->Authorize(Caller(context), Action::kControl, req->session_id());
    auto s = registry_->FindOrThrow(req->session_id());
    s->RequestPause(true);
    DescribeSession(*s, out);
  });
}

Status SessionServiceImpl::ResumeSession(grpc::ServerContext* context, const hapsim::v1::SessionRef* req,
                                         hapsim::v1::SessionInfo* out) {
  return Guarded("ResumeSession", [&] {
    policy_->Authorize(Caller(context), Action::kControl, req->session_id());
    auto s = registry_->FindOrThrow(req->session_id());
    s->RequestPause(false);
    DescribeSession(*s, out);
  });
}

Status SessionServiceImpl::ResetSession(grpc::ServerContext* context, const hapsim::v1::SessionRef* req,
                                        hapsim::v1::SessionInfo* out) {
  return Guarded("ResetSession", [&] {
    policy_->Authorize(Caller(context), Action::kControl, req->session_id());
    auto s = registry_->FindOrThrow(req->session_id());
    s->RequestReset();
    DescribeSession(*s, out);
  });
}

Status SessionServiceImpl::GetSnapshot(grpc::ServerContext* context, const hapsim::v1::SessionRef* req,
                                       hapsim::v1::MeshSnapshot* out) {
  return Guarded("GetSnapshot", [&] {
    policy_->Authorize(Caller(context), Action::kView, req->session_id());
    auto s = registry_->FindOrThrow(req->session_id());
    const auto snap = hub_->LatestSnapshot(*s);
    if (!snap) throw ServiceError(ErrorCode::kFailedPrecondition, "session has no snapshot yet; retry shortly");
    out->set_session_id(s->id());
    out->set_sim_time_s(snap->sim_time_s);
    out->set_topology_version(snap->topology_version);
    // Compacted: live vertices in slot order, triangles renumbered to them.
    std::vector<std::uint32_t> index_of(snap->vertex_slots, 0);
    std::uint32_t live = 0;
    for (std::uint32_t v = 0; v < snap->vertex_slots; ++v) {
      if (!snap->vertex_live[v]) continue;
      index_of[v] = live++;
      for (int k = 0; k < 3; ++k) out->add_positions_m(snap->vertices_m(k, static_cast<Eigen::Index>(v)));
    }
    for (std::uint32_t t = 0; t < snap->triangle_slots; ++t) {
      if (!snap->triangle_live[t]) continue;
      for (const std::uint32_t v : snap->triangles[t]) out->add_triangles(index_of[v]);
      out->add_triangle_parts(snap->triangle_parts[t]);
    }
    if (snap->part_names) {
      for (const auto& name : *snap->part_names) out->add_part_names(name);
    }
  });
}

Status SessionServiceImpl::SubmitScores(grpc::ServerContext* context, const hapsim::v1::SubmitScoresRequest* req,
                                        hapsim::v1::ScoreReport* out) {
  return Guarded("SubmitScores", [&] {
    policy_->Authorize(Caller(context), Action::kScore, req->session_id());
    if (req->indicators_size() > 64) throw ServiceError(ErrorCode::kInvalidArgument, "more than 64 indicator scores");
    const auto session = registry_->FindOrThrow(req->session_id());  // scores belong to a live session
    scores_->Submit(req->session_id(), session->config().scene, req->expert(),
                    std::vector<double>(req->indicators().begin(), req->indicators().end()));
    scores_->Report(req->session_id(), out);
  });
}

Status SessionServiceImpl::GetScores(grpc::ServerContext* context, const hapsim::v1::ScoreQuery* req,
                                     hapsim::v1::ScoreReport* out) {
  return Guarded("GetScores", [&] {
    const auto who = Caller(context);
    const std::string& id = req->session_id();
    if (!id.empty()) policy_->Authorize(who, Action::kView, id);
    // A session that exists (live, or in a class) but nobody has scored yet
    // has an empty report; NOT_FOUND is for sessions that do not exist.
    if (!id.empty() && !scores_->Scored(id)) {
      if (!registry_->Find(id) && !policy_->ClassOf(id))
        throw ServiceError(ErrorCode::kNotFound, "no session '" + id.substr(0, 80) + "' (and no scores for it)");
      out->set_mu(core::assessment::ComprehensiveScoreResult{}.mu);
      return;
    }
    scores_->Report(id, out, [&](const std::string& other) { return policy_->Allows(who, Action::kView, other); });
  });
}

Status SessionServiceImpl::JoinSession(grpc::ServerContext* context, const hapsim::v1::SessionRef* req,
                                       hapsim::v1::JoinSessionResponse* out) {
  return Guarded("JoinSession", [&] {
    const auto who = Caller(context);
    policy_->Authorize(who, Action::kJoin, req->session_id());
    const auto s = registry_->FindOrThrow(req->session_id());
    out->set_session_id(s->id());
    out->set_dds_partition(dds::SessionPartition(s->id()));
    out->set_dds_domain(dds_domain_);
    out->set_scene(s->config().scene);
    spdlog::info("{} joined session '{}' (DDS partition {})", who ? who->name : "a development client", s->id(),
                 out->dds_partition());
  });
}

SessionServiceImpl::Placement SessionServiceImpl::PlacementOf(const std::string& session_id) const {
  const ClassDef* cls = policy_->ClassOf(session_id);
  if (!cls) return {};
  return {cls->Find(session_id)->trainee, cls->targets};
}

const std::vector<std::string>* SessionServiceImpl::ClassSessions(const std::string& name,
                                                                  std::vector<std::string>* storage) const {
  if (!policy_->enabled()) {
    if (!name.empty()) {
      throw ServiceError(ErrorCode::kNotFound, "this server has no class config: watch the whole server with an "
                                               "empty class name");
    }
    return nullptr;
  }
  const ClassDef* cls = policy_->FindClass(name);
  if (!cls) throw ServiceError(ErrorCode::kNotFound, "no class '" + name.substr(0, 80) + "'");
  for (const auto& s : cls->sessions) storage->push_back(s.id);
  return storage;
}

Status SessionServiceImpl::WatchClass(grpc::ServerContext* context, const hapsim::v1::WatchClassRequest* req,
                                      grpc::ServerWriter<hapsim::v1::ClassStatus>* writer) {
  return WatchClassOn(context, req, writer);
}

Status SessionServiceImpl::WatchClassOn(grpc::ServerContext* context, const hapsim::v1::WatchClassRequest* req,
                                        grpc::ServerWriterInterface<hapsim::v1::ClassStatus>* writer) {
  std::vector<std::string> storage;
  const std::vector<std::string>* ids = nullptr;
  double rate_hz = req->rate_hz();
  const Status allowed = Guarded("WatchClass", [&] {
    const auto who = Caller(context);
    policy_->Authorize(who, Action::kWatchClass, req->class_name());
    ids = ClassSessions(req->class_name(), &storage);
    if (rate_hz == 0.0) rate_hz = kDefaultWatchRateHz;
    if (!std::isfinite(rate_hz) || rate_hz < 0.1 || rate_hz > kMaxWatchRateHz) {
      throw ServiceError(ErrorCode::kInvalidArgument, "rate_hz must be 0 (10 Hz) or within [0.1, 50]");
    }
  });
  if (!allowed.ok()) return allowed;
  {
    std::lock_guard lock(watch_mutex_);
    if (stopping_) return {grpc::StatusCode::UNAVAILABLE, "the server is stopping"};
    if (watch_streams_ >= kMaxWatchStreams) {
      return {grpc::StatusCode::RESOURCE_EXHAUSTED,
              "this server already serves " + std::to_string(kMaxWatchStreams) + " class views"};
    }
    ++watch_streams_;
  }
  ClassStatusBuilder builder(registry_, hub_, scores_);
  const auto period = std::chrono::duration_cast<std::chrono::steady_clock::duration>(
      std::chrono::duration<double>(1.0 / rate_hz));
  auto next = std::chrono::steady_clock::now();
  while (true) {
    hapsim::v1::ClassStatus status;
    status.set_class_name(req->class_name());
    builder.Fill(ids, &status);
    if (!writer->Write(status)) break;  // the instructor went away
    next += period;
    std::unique_lock lock(watch_mutex_);
    if (watch_wake_.wait_until(lock, next, [&] { return stopping_; })) break;
    if (context->IsCancelled()) break;
  }
  std::lock_guard lock(watch_mutex_);
  --watch_streams_;
  return Status::OK;
}

Status SessionServiceImpl::GetTrials(grpc::ServerContext* context, const hapsim::v1::TrialQuery* req,
                                     hapsim::v1::TrialReport* out) {
  return Guarded("GetTrials", [&] {
    const auto who = Caller(context);
    policy_->Authorize(who, Action::kWatchClass, req->class_name());
    std::vector<std::string> storage;
    const std::vector<std::string>* ids = ClassSessions(req->class_name(), &storage);
    if (!trials_) throw ServiceError(ErrorCode::kFailedPrecondition, "this server keeps no trial metrics");
    const auto rows = trials_->Trials([&](const std::string& id) {
      return !ids || std::find(ids->begin(), ids->end(), id) != ids->end();
    });
    out->set_trials(static_cast<std::uint32_t>(rows.size()));
    out->set_csv(FormatTrialsCsv(rows, [&](const std::string& id) -> std::string {
      const auto score = scores_->SummaryOf(id);
      if (!score) return "";
      char text[32];
      std::snprintf(text, sizeof text, "%.4f", score->score);
      return text;
    }));
  });
}

void SessionServiceImpl::Stop() {
  std::lock_guard lock(watch_mutex_);
  stopping_ = true;
  watch_wake_.notify_all();
}

Status SessionServiceImpl::PushScenario(grpc::ServerContext* context, const hapsim::v1::PushScenarioRequest* req,
                                        hapsim::v1::PushScenarioResponse* out) {
  return Guarded("PushScenario", [&] {
    const auto who = Caller(context);
    policy_->Authorize(who, Action::kPushScenario, req->class_name());
    std::vector<std::string> storage;
    const std::vector<std::string>* ids = ClassSessions(req->class_name(), &storage);
    std::vector<std::string> all;
    if (!ids) {
      for (const auto& s : registry_->List()) all.push_back(s->id());
      ids = &all;
    }
    if (req->params_size() > 64) throw ServiceError(ErrorCode::kInvalidArgument, "more than 64 scene parameters");
    core::SceneSpec spec;
    spec.name = req->scene().empty() ? "tissue_block" : req->scene();
    for (const auto& [key, value] : req->params()) {
      if (!std::isfinite(value)) {
        throw ServiceError(ErrorCode::kInvalidArgument, "scene parameter '" + key.substr(0, 80) + "' is not finite");
      }
      spec.params.emplace(key, value);
    }
    // Check the scenario once before touching any session: a bad one leaves
    // the class as it was.
    try {
      (void)core::MakeScene(spec);
    } catch (const std::invalid_argument& e) {
      throw ServiceError(ErrorCode::kInvalidArgument, e.what());
    }
    for (const auto& id : *ids) {
      Placement placement = PlacementOf(id);
      if (const auto existing = registry_->Find(id)) {
        placement.trainee = existing->config().owner;  // keeps a trainee named at creation
        try {
          registry_->Close(id);
        } catch (const ServiceError&) {  // closed meanwhile
        }
      }
      DescribeSession(*registry_->Create(id, spec.name, placement.trainee, spec.params, placement.targets),
                      out->add_sessions());
    }
    spdlog::info("{} pushed scene '{}' to {} sessions of class '{}'", who ? who->name : "a development client",
                 spec.name, ids->size(), req->class_name());
  });
}

}  // namespace hapsim::service
