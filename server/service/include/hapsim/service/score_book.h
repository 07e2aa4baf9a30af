// The instructor's score sheets: for each session, the 7 indicator scores
// (0..10) each expert submitted. Reports use the comprehensive weighted score
// of the acupuncture paper §4.2 (hapsim::core assessment), computed over the
// whole class: objective weights come from the spread across sessions.
#pragma once
#include <map>
#include <mutex>
#include <string>
#include <vector>

#include "hapsim/v1/session.pb.h"

namespace hapsim::service {

class ScoreBook {
 public:
  static constexpr std::size_t kIndicators = 7;
  // Bounds on what clients can make the server keep (sheets outlive their
  // session, for the class report): a class has tens of trainees and a few
  // experts, so these are far above use and cap the book at ~6 MB.
  static constexpr std::size_t kMaxExpertsPerSession = 32;
  static constexpr std::size_t kMaxScoredSessions = 1024;

  // Throws ServiceError(kInvalidArgument) unless there are exactly 7 finite
  // values in [0, 10]. The same expert scoring a session again replaces the
  // earlier sheet. A new expert beyond kMaxExpertsPerSession, or a new
  // session beyond kMaxScoredSessions, is kResourceExhausted.
  void Submit(const std::string& session_id, const std::string& expert, const std::vector<double>& indicators);
  // session_id empty: every scored session; otherwise just that one (class
  // weights are still computed over all sessions). Throws kNotFound if the
  // session has no scores.
  void Report(const std::string& session_id, hapsim::v1::ScoreReport* out) const;

 private:
  mutable std::mutex mutex_;
  // session -> expert -> 7 indicators
  std::map<std::string, std::map<std::string, std::vector<double>>> sheets_;
};

}  // namespace hapsim::service
