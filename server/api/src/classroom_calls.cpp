#include "hapsim/api/classroom_calls.h"

#include <spdlog/spdlog.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>

#include "hapsim/api/call_status.h"
#include "hapsim/api/class_status.h"
#include "hapsim/api/session_service.h"
#include "hapsim/core/assessment/scoring.h"
#include "hapsim/core/scenes/scene.h"

namespace hapsim::service {

using grpc::Status;
using grpc::StatusCode;

ClassroomCalls::ClassroomCalls(SessionRegistry* registry, const ViewerHub* hub, ScoreBook* scores,
                               const AccessPolicy* policy, const TrialBook* trials)
    : registry_(registry),
      hub_(hub),
      scores_(scores),
      policy_(policy ? policy : &OpenAccessPolicy()),
      trials_(trials) {}

std::optional<Principal> ClassroomCalls::Caller(const grpc::ServerContext* context) const {
  return AuthenticateCall(*policy_, context);
}

Status ClassroomCalls::SubmitScores(grpc::ServerContext* context, const hapsim::v1::SubmitScoresRequest* req,
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

Status ClassroomCalls::GetScores(grpc::ServerContext* context, const hapsim::v1::ScoreQuery* req,
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

const std::vector<std::string>* ClassroomCalls::ClassSessions(const std::string& name,
                                                              std::vector<std::string>* storage) const {
  if (!policy_->enabled()) {
    if (!name.empty()) {
      throw ServiceError(ErrorCode::kNotFound,
                         "this server has no class config: watch the whole server with an "
                         "empty class name");
    }
    return nullptr;
  }
  const ClassDef* cls = policy_->FindClass(name);
  if (!cls) throw ServiceError(ErrorCode::kNotFound, "no class '" + name.substr(0, 80) + "'");
  for (const auto& s : cls->sessions) storage->push_back(s.id);
  return storage;
}

Status ClassroomCalls::WatchClassOn(grpc::ServerContext* context, const hapsim::v1::WatchClassRequest* req,
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
  const auto period =
      std::chrono::duration_cast<std::chrono::steady_clock::duration>(std::chrono::duration<double>(1.0 / rate_hz));
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

Status ClassroomCalls::GetTrials(grpc::ServerContext* context, const hapsim::v1::TrialQuery* req,
                                 hapsim::v1::TrialReport* out) {
  return Guarded("GetTrials", [&] {
    const auto who = Caller(context);
    policy_->Authorize(who, Action::kWatchClass, req->class_name());
    std::vector<std::string> storage;
    const std::vector<std::string>* ids = ClassSessions(req->class_name(), &storage);
    if (!trials_) throw ServiceError(ErrorCode::kFailedPrecondition, "this server keeps no trial metrics");
    const auto rows = trials_->Trials(
        [&](const std::string& id) { return !ids || std::find(ids->begin(), ids->end(), id) != ids->end(); });
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

void ClassroomCalls::Stop() {
  std::lock_guard lock(watch_mutex_);
  stopping_ = true;
  watch_wake_.notify_all();
}

Status ClassroomCalls::PushScenario(grpc::ServerContext* context, const hapsim::v1::PushScenarioRequest* req,
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
      std::string trainee = policy_->TraineeOf(id);
      if (const auto existing = registry_->Find(id)) {
        trainee = existing->config().owner;  // keeps a trainee named at creation
        try {
          registry_->Close(id);
        } catch (const ServiceError&) {  // closed meanwhile
        }
      }
      DescribeSession(*registry_->Create(id, spec.name, trainee, spec.params), out->add_sessions());
    }
    spdlog::info("{} pushed scene '{}' to {} sessions of class '{}'", who ? who->name : "a development client",
                 spec.name, ids->size(), req->class_name());
  });
}

}  // namespace hapsim::service
