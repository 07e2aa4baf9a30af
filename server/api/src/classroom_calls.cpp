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

namespace {

// The classroom's report on the wire.
void FillScoreReport(const ScoreReport& report, hapsim::v1::ScoreReport* out) {
  out->set_mu(report.mu);
  for (const double w : report.subjective_weights) out->add_subjective_weights(w);
  for (const double w : report.objective_weights) out->add_objective_weights(w);
  for (const double w : report.combined_weights) out->add_combined_weights(w);
  out->set_class_mean_score(report.class_mean_score);
  for (const SessionScoreSheet& sheet : report.sessions) {
    hapsim::v1::SessionScore* s = out->add_sessions();
    s->set_session_id(sheet.session_id);
    s->set_experts(sheet.experts);
    for (const double x : sheet.mean_indicators) s->add_mean_indicators(x);
    for (const double w : sheet.objective_weights) s->add_objective_weights(w);
    for (const double w : sheet.combined_weights) s->add_combined_weights(w);
    s->set_comprehensive_score(sheet.comprehensive_score);
    s->set_scheme(sheet.scheme);
  }
}

// A class view's rate: 0 asks for the default.
double CheckedWatchRateHz(double rate_hz) {
  if (rate_hz == 0.0) rate_hz = ClassroomCalls::kDefaultWatchRateHz;
  if (!std::isfinite(rate_hz) || rate_hz < 0.1 || rate_hz > ClassroomCalls::kMaxWatchRateHz) {
    throw ServiceError(ErrorCode::kInvalidArgument, "rate_hz must be 0 (10 Hz) or within [0.1, 50]");
  }
  return rate_hz;
}

// The scenario a PushScenario asks for, checked once before any session is
// touched: a bad one leaves the class as it was.
core::SceneSpec PushedScenarioSpec(const hapsim::v1::PushScenarioRequest& req) {
  if (req.params_size() > 64) throw ServiceError(ErrorCode::kInvalidArgument, "more than 64 scene parameters");
  core::SceneSpec spec;
  spec.name = req.scene().empty() ? "tissue_block" : req.scene();
  for (const auto& [key, value] : req.params()) {
    if (!std::isfinite(value)) {
      throw ServiceError(ErrorCode::kInvalidArgument, "scene parameter '" + key.substr(0, 80) + "' is not finite");
    }
    spec.params.emplace(key, value);
  }
  try {
    (void)core::MakeScene(spec);
  } catch (const std::invalid_argument& e) {
    throw ServiceError(ErrorCode::kInvalidArgument, e.what());
  }
  return spec;
}

}  // namespace

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
    FillScoreReport(scores_->Report(req->session_id()), out);
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
    FillScoreReport(
        scores_->Report(id, [&](const std::string& other) { return policy_->Allows(who, Action::kView, other); }), out);
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
    rate_hz = CheckedWatchRateHz(rate_hz);
  });
  if (!allowed.ok()) return allowed;
  if (const Status admitted = AdmitWatchStream(); !admitted.ok()) return admitted;
  StreamClassStatus(context, req->class_name(), ids, rate_hz, writer);
  std::lock_guard lock(watch_mutex_);
  --watch_streams_;
  return Status::OK;
}

Status ClassroomCalls::AdmitWatchStream() {
  std::lock_guard lock(watch_mutex_);
  if (stopping_) return {grpc::StatusCode::UNAVAILABLE, "the server is stopping"};
  if (watch_streams_ >= kMaxWatchStreams) {
    return {grpc::StatusCode::RESOURCE_EXHAUSTED,
            "this server already serves " + std::to_string(kMaxWatchStreams) + " class views"};
  }
  ++watch_streams_;
  return Status::OK;
}

void ClassroomCalls::StreamClassStatus(grpc::ServerContext* context, const std::string& class_name,
                                       const std::vector<std::string>* ids, double rate_hz,
                                       grpc::ServerWriterInterface<hapsim::v1::ClassStatus>* writer) {
  ClassStatusBuilder builder(registry_, hub_, scores_);
  const auto period =
      std::chrono::duration_cast<std::chrono::steady_clock::duration>(std::chrono::duration<double>(1.0 / rate_hz));
  auto next = std::chrono::steady_clock::now();
  while (true) {
    hapsim::v1::ClassStatus status;
    status.set_class_name(class_name);
    builder.Fill(ids, &status);
    if (!writer->Write(status)) break;  // the instructor went away
    next += period;
    std::unique_lock lock(watch_mutex_);
    if (watch_wake_.wait_until(lock, next, [&] { return stopping_; })) break;
    if (context->IsCancelled()) break;
  }
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
    const core::SceneSpec spec = PushedScenarioSpec(*req);
    for (const auto& id : *ids) RecreateSession(id, spec, out);
    spdlog::info("{} pushed scene '{}' to {} sessions of class '{}'", who ? who->name : "a development client",
                 spec.name, ids->size(), req->class_name());
  });
}

void ClassroomCalls::RecreateSession(const std::string& id, const core::SceneSpec& spec,
                                     hapsim::v1::PushScenarioResponse* out) {
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

}  // namespace hapsim::service
