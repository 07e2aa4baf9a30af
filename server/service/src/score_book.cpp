#include "hapsim/service/score_book.h"

#include <cmath>

#include "hapsim/core/assessment/scoring.h"
#include "hapsim/service/errors.h"

namespace hapsim::service {

void ScoreBook::Submit(const std::string& session_id, const std::string& expert,
                       const std::vector<double>& indicators) {
  if (indicators.size() != kIndicators) {
    throw ServiceError(ErrorCode::kInvalidArgument, "expected exactly 7 indicator scores, got " +
                                                        std::to_string(indicators.size()));
  }
  for (const double x : indicators) {
    if (!std::isfinite(x) || x < 0.0 || x > 10.0) {
      throw ServiceError(ErrorCode::kInvalidArgument, "indicator scores must be within [0, 10]");
    }
  }
  if (expert.size() > 128) throw ServiceError(ErrorCode::kInvalidArgument, "expert name longer than 128 characters");
  const std::string name = expert.empty() ? "anonymous" : expert;
  std::lock_guard lock(mutex_);
  const auto session = sheets_.find(session_id);
  if (session == sheets_.end() && sheets_.size() >= kMaxScoredSessions) {
    throw ServiceError(ErrorCode::kResourceExhausted,
                       "the score book holds " + std::to_string(kMaxScoredSessions) + " sessions already");
  }
  if (session != sheets_.end() && !session->second.count(name) && session->second.size() >= kMaxExpertsPerSession) {
    throw ServiceError(ErrorCode::kResourceExhausted, "session '" + session_id.substr(0, 80) + "' has sheets from " +
                                                          std::to_string(kMaxExpertsPerSession) + " experts already");
  }
  sheets_[session_id][name] = indicators;
}

void ScoreBook::Report(const std::string& session_id, hapsim::v1::ScoreReport* out) const {
  std::lock_guard lock(mutex_);
  if (!session_id.empty() && !sheets_.count(session_id)) {
    throw ServiceError(ErrorCode::kNotFound, "no scores for session '" + session_id.substr(0, 80) + "'");
  }
  if (sheets_.empty()) {  // nothing scored yet: the class weights only, no sessions
    const Eigen::VectorXd alpha = core::assessment::DelphiWeights();
    for (Eigen::Index j = 0; j < alpha.size(); ++j) out->add_subjective_weights(alpha[j]);
    out->set_mu(core::assessment::ComprehensiveScoreResult{}.mu);
    return;
  }
  // One row per scored session: the mean over its experts.
  std::vector<std::string> ids;
  Eigen::MatrixXd class_scores(static_cast<Eigen::Index>(sheets_.size()), static_cast<Eigen::Index>(kIndicators));
  Eigen::Index row = 0;
  for (const auto& [id, by_expert] : sheets_) {
    Eigen::VectorXd mean = Eigen::VectorXd::Zero(kIndicators);
    for (const auto& [expert, values] : by_expert) {
      mean += Eigen::Map<const Eigen::VectorXd>(values.data(), kIndicators);
    }
    class_scores.row(row++) = mean / static_cast<double>(by_expert.size());
    ids.push_back(id);
  }
  const auto result = core::assessment::ComprehensiveScores(class_scores);
  for (Eigen::Index j = 0; j < result.subjective_weights.size(); ++j) {
    out->add_subjective_weights(result.subjective_weights[j]);
    out->add_objective_weights(result.objective_weights[j]);
    out->add_combined_weights(result.combined_weights[j]);
  }
  out->set_mu(result.mu);
  out->set_class_mean_score(result.scores.size() ? result.scores.mean() : 0.0);
  for (std::size_t i = 0; i < ids.size(); ++i) {
    if (!session_id.empty() && ids[i] != session_id) continue;
    auto* s = out->add_sessions();
    s->set_session_id(ids[i]);
    s->set_experts(static_cast<std::uint32_t>(sheets_.at(ids[i]).size()));
    for (Eigen::Index j = 0; j < class_scores.cols(); ++j) s->add_mean_indicators(class_scores(static_cast<Eigen::Index>(i), j));
    s->set_comprehensive_score(result.scores[static_cast<Eigen::Index>(i)]);
  }
}

}  // namespace hapsim::service
