#include "hapsim/api/session_service.h"

#include <spdlog/spdlog.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <thread>

#include "hapsim/api/call_status.h"
#include "hapsim/common/clock.h"
#include "hapsim/core/assessment/scoring.h"
#include "hapsim/core/scenes/scene.h"
#include "hapsim/dds/partition.h"

namespace hapsim::service {

using grpc::Status;
using grpc::StatusCode;

SessionServiceImpl::SessionServiceImpl(SessionRegistry* registry, const ViewerHub* hub, ScoreBook* scores,
                                       const AccessPolicy* policy, std::uint32_t dds_domain, const TrialBook* trials,
                                       ResultsStore* store, std::string recordings_dir, const PeerLocator* peers)
    : registry_(registry),
      hub_(hub),
      policy_(policy ? policy : &OpenAccessPolicy()),
      dds_domain_(dds_domain),
      classroom_(registry, hub, scores, policy, trials),
      recordings_(store, std::move(recordings_dir), policy),
      replays_(registry, &recordings_, policy),
      locate_(registry, policy_, peers) {}

std::optional<Principal> SessionServiceImpl::Caller(const grpc::ServerContext* context) const {
  return AuthenticateCall(*policy_, context);
}

void DescribeSession(const Session& s, hapsim::v1::SessionInfo* info) {
  const auto& c = s.counters();
  info->set_session_id(s.id());
  info->set_scene(s.config().scene);
  info->set_owner(s.config().owner);
  info->set_paused(s.paused());
  info->set_sim_time_s(c.tick.sim_time_s.load());
  info->set_ticks(c.tick.ticks.load());
  info->set_late_ticks(c.tick.late_ticks.load());
  info->set_device_clocked_ticks(c.tick.device_clocked_ticks.load());
  info->set_poses_from_other_devices(c.poses.from_other_devices.load());
  info->set_poses_stale(c.poses.stale.load());
  info->set_viewer_frames_coalesced(c.viewers.frames_coalesced.load());
  info->set_poses_wrong_session(c.poses.wrong_session.load());
  info->set_owning_device_id(c.tick.owning_device_id.load());
  info->set_device_streaming(c.tick.device_streaming.load());
  info->set_max_tick_lateness_s(static_cast<double>(c.tick.max_lateness_ns.load()) * 1e-9);
  info->set_viewers(c.viewers.connected.load());
  info->set_poses_received(c.poses.received.load());
  info->set_poses_rejected(c.poses.rejected.load());
  info->set_force_models_sent(c.tick.force_models_sent.load());
  info->set_force_models_held(c.tick.force_models_held.load());
  info->set_poses_unused(c.tick.poses_unused.load());
  info->set_numerical_resets(c.tick.numerical_resets.load());
  info->set_tick_period_s(s.config().tick_period_s);
  info->set_peak_tool_force_n(c.tick.peak_tool_force_N.load());
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
    std::string owner = req->owner().empty() ? policy_->TraineeOf(req->session_id()) : req->owner();
    if (req->params_size() > 64) throw ServiceError(ErrorCode::kInvalidArgument, "more than 64 scene parameters");
    std::map<std::string, double> params;
    for (const auto& [key, value] : req->params()) {
      if (!std::isfinite(value)) {
        throw ServiceError(ErrorCode::kInvalidArgument, "scene parameter '" + key.substr(0, 80) + "' is not finite");
      }
      params.emplace(key, value);
    }
    created = registry_->Create(req->session_id(), req->scene(), std::move(owner), std::move(params));
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

// A session nobody watches publishes its snapshots without the mesh: ask
// for it and wait for the frame pump to take one that has it (a frame or two,
// ~17-33 ms at 60 Hz). nullptr if the pump has taken no snapshot of the
// session yet (at once, as before there were meshless ones) or none with the
// mesh came within kMeshWait.
std::shared_ptr<const SceneSnapshot> SessionServiceImpl::SnapshotWithMesh(Session& s,
                                                                          grpc::ServerContext& context) const {
  constexpr std::int64_t kMeshWantedNs = 2'000'000'000;  // long enough for a client's retry to find it
  constexpr auto kMeshWait = std::chrono::milliseconds(500);
  auto snap = hub_->LatestSnapshot(s);
  if (!snap || snap->has_mesh) return snap;
  s.WantMeshUntil(common::SteadyNowNs() + kMeshWantedNs);
  const auto give_up = std::chrono::steady_clock::now() + kMeshWait;
  while (std::chrono::steady_clock::now() < give_up && !context.IsCancelled()) {
    std::this_thread::sleep_for(std::chrono::milliseconds(2));
    snap = hub_->LatestSnapshot(s);
    if (snap && snap->has_mesh) return snap;
  }
  return nullptr;
}

Status SessionServiceImpl::GetSnapshot(grpc::ServerContext* context, const hapsim::v1::SessionRef* req,
                                       hapsim::v1::MeshSnapshot* out) {
  return Guarded("GetSnapshot", [&] {
    policy_->Authorize(Caller(context), Action::kView, req->session_id());
    auto s = registry_->FindOrThrow(req->session_id());
    const auto snap = SnapshotWithMesh(*s, *context);
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

}  // namespace hapsim::service
