#include "hapsim/classroom/score_book.h"

#include <cmath>

#include "hapsim/core/assessment/ahp.h"
#include "hapsim/core/assessment/scoring.h"
#include "hapsim/runtime/errors.h"

namespace hapsim::service {

ScoringScheme SchemeForScene(const std::string& scene) {
  if (scene == "cutting") return ScoringScheme::kCuttingResidents;
  if (scene == "vessel") return ScoringScheme::kVesselAhp;
  return ScoringScheme::kDelphiMsd;
}

const char* SchemeName(ScoringScheme scheme) {
  switch (scheme) {
    case ScoringScheme::kDelphiMsd: return "delphi_msd";
    case ScoringScheme::kCuttingResidents: return "cutting_residents";
    case ScoringScheme::kVesselAhp: return "vessel_ahp";
  }
  return "?";
}

std::size_t IndicatorCount(ScoringScheme scheme) { return scheme == ScoringScheme::kVesselAhp ? 9 : 7; }

ScoreBook::ScoreBook() {
  const auto j = core::assessment::DefaultVesselJudgements();
  vessel_weights_ = core::assessment::AhpHierarchy(j.criteria, j.indicators).global_weights;
}

void ScoreBook::Submit(const std::string& session_id, const std::string& scene, const std::string& expert,
                       const std::vector<double>& indicators) {
  const ScoringScheme scheme = SchemeForScene(scene);
  const std::size_t count = IndicatorCount(scheme);
  if (indicators.size() != count) {
    throw ServiceError(ErrorCode::kInvalidArgument, "a " + scene + " session is scored on exactly " +
                                                        std::to_string(count) + " indicators (" + SchemeName(scheme) +
                                                        "), got " + std::to_string(indicators.size()));
  }
  for (const double x : indicators) {
    if (!std::isfinite(x) || x < 0.0 || x > 10.0) {
      throw ServiceError(ErrorCode::kInvalidArgument, "indicator scores must be within [0, 10]");
    }
  }
  if (expert.size() > 128) throw ServiceError(ErrorCode::kInvalidArgument, "expert name longer than 128 characters");
  const std::string name = expert.empty() ? "anonymous" : expert;
  AddSheet(session_id, scene, name, indicators);
  if (observer_) observer_(session_id, scene, name, indicators);
}

void ScoreBook::AddSheet(const std::string& session_id, const std::string& scene, const std::string& name,
                         const std::vector<double>& indicators) {
  std::lock_guard lock(mutex_);
  auto session = sheets_.find(session_id);
  if (session == sheets_.end() && sheets_.size() >= kMaxScoredSessions) {
    throw ServiceError(ErrorCode::kResourceExhausted,
                       "the score book holds " + std::to_string(kMaxScoredSessions) + " sessions already");
  }
  if (session != sheets_.end() && session->second.scene != scene) {
    session->second = Sheets{};  // a new scenario: a new trial, new sheets
  }
  if (session != sheets_.end() && !session->second.by_expert.count(name) &&
      session->second.by_expert.size() >= kMaxExpertsPerSession) {
    throw ServiceError(ErrorCode::kResourceExhausted, "session '" + session_id.substr(0, 80) + "' has sheets from " +
                                                          std::to_string(kMaxExpertsPerSession) + " experts already");
  }
  Sheets& sheets = sheets_[session_id];
  sheets.scene = scene;
  sheets.by_expert[name] = indicators;
}

SessionScoreSheet ScoreBook::Describe(const std::string& id, const Sheets& sheets) const {
  const ScoringScheme scheme = SchemeForScene(sheets.scene);
  const auto n = static_cast<Eigen::Index>(IndicatorCount(scheme));
  // One row per expert: the raters are the samples (acupuncture paper eq. 10-11).
  Eigen::MatrixXd x(static_cast<Eigen::Index>(sheets.by_expert.size()), n);
  Eigen::Index row = 0;
  for (const auto& [expert, values] : sheets.by_expert) {
    x.row(row++) = Eigen::Map<const Eigen::RowVectorXd>(values.data(), n);
  }
  const Eigen::VectorXd mean = x.colwise().mean().transpose();
  SessionScoreSheet out;
  out.session_id = id;
  out.experts = static_cast<std::uint32_t>(x.rows());
  out.mean_indicators.assign(mean.data(), mean.data() + n);
  Eigen::VectorXd weights;
  if (scheme == ScoringScheme::kDelphiMsd) {
    const auto r = core::assessment::ComprehensiveScores(x);
    out.objective_weights.assign(r.objective_weights.data(), r.objective_weights.data() + n);
    weights = r.combined_weights;
  } else {
    weights = scheme == ScoringScheme::kCuttingResidents ? core::assessment::CuttingDelphiWeights() : vessel_weights_;
  }
  out.combined_weights.assign(weights.data(), weights.data() + n);
  // mean_i sum_j w_j x_ij = sum_j w_j mean_j
  out.comprehensive_score = core::assessment::WeightedScore(weights, mean);
  out.scheme = SchemeName(scheme);
  return out;
}

bool ScoreBook::Scored(const std::string& session_id) const {
  std::lock_guard lock(mutex_);
  return sheets_.count(session_id) > 0;
}

ScoreReport ScoreBook::Report(const std::string& session_id,
                              const std::function<bool(const std::string&)>& visible) const {
  std::lock_guard lock(mutex_);
  ScoreReport out;
  out.mu = core::assessment::ComprehensiveScoreResult{}.mu;
  const Eigen::VectorXd alpha = core::assessment::DelphiWeights();
  if (!session_id.empty()) {
    const auto found = sheets_.find(session_id);
    if (found == sheets_.end()) {
      throw ServiceError(ErrorCode::kNotFound, "no scores for session '" + session_id.substr(0, 80) + "'");
    }
    const SessionScoreSheet& s = out.sessions.emplace_back(Describe(found->first, found->second));
    if (SchemeForScene(found->second.scene) == ScoringScheme::kDelphiMsd) {
      out.subjective_weights.assign(alpha.data(), alpha.data() + alpha.size());
    }
    out.objective_weights = s.objective_weights;
    out.combined_weights = s.combined_weights;
    out.class_mean_score = s.comprehensive_score;
    return out;
  }
  out.subjective_weights.assign(alpha.data(), alpha.data() + alpha.size());
  double total = 0.0;
  for (const auto& [id, sheets] : sheets_) {
    if (visible && !visible(id)) continue;
    total += out.sessions.emplace_back(Describe(id, sheets)).comprehensive_score;
  }
  out.class_mean_score = out.sessions.empty() ? 0.0 : total / static_cast<double>(out.sessions.size());
  return out;
}

std::optional<ScoreBook::Summary> ScoreBook::SummaryOf(const std::string& session_id) const {
  std::lock_guard lock(mutex_);
  const auto found = sheets_.find(session_id);
  if (found == sheets_.end()) return std::nullopt;
  const SessionScoreSheet s = Describe(found->first, found->second);
  return Summary{s.experts, s.comprehensive_score};
}

}  // namespace hapsim::service
