// The instructor's score sheets: for each session, the indicator scores
// (0..10) each expert submitted, scored as the paper of the session's scene
// does (docs/classroom.md#assessment):
//   acupuncture and the other needle/probe scenes: the acupuncture paper's
//     Delphi + mean-square-deviation weights (mu = 0.4), 7 indicators; the
//     objective weights come from this session's raters' disagreement, so a
//     trainee's score depends on their own raters only
//   cutting: the cutting paper's residents' score, 7 indicators, its fixed
//     Delphi weights
//   vessel: the vascular paper's AHP, 9 indicators, weights from pairwise
//     judgements (hapsim's defaults; refused if CR > 0.1)
// A session's score is the mean over its experts of f = sum_j w_j x_j.
#pragma once
#include <functional>
#include <map>
#include <mutex>
#include <optional>
#include <string>
#include <vector>

#include <Eigen/Core>

namespace hapsim::service {

enum class ScoringScheme { kDelphiMsd, kCuttingResidents, kVesselAhp };
ScoringScheme SchemeForScene(const std::string& scene);
const char* SchemeName(ScoringScheme scheme);
std::size_t IndicatorCount(ScoringScheme scheme);  // 7, 7, 9

// One session's score: its experts' mean indicators, the weights applied and
// the comprehensive score (GetScores carries it as a SessionScore).
struct SessionScoreSheet {
  std::string session_id;
  std::uint32_t experts = 0;
  std::vector<double> mean_indicators;
  std::vector<double> objective_weights;  // Delphi + MSD scheme only: from this session's raters
  std::vector<double> combined_weights;
  double comprehensive_score = 0.0;
  std::string scheme;  // SchemeName
};

// The scores of one session or of all visible ones (GetScores' ScoreReport).
struct ScoreReport {
  double mu = 0.0;                         // the Delphi + MSD scheme's subjective share
  std::vector<double> subjective_weights;  // the Delphi weights
  std::vector<double> objective_weights;   // one session asked: its own
  std::vector<double> combined_weights;    // one session asked: its own
  double class_mean_score = 0.0;
  std::vector<SessionScoreSheet> sessions;
};

class ScoreBook {
 public:
  // Bounds on what clients can make the server keep (sheets outlive their
  // session, for the class report): a class has tens of trainees and a few
  // experts, so these are far above use and cap the book at ~6 MB.
  static constexpr std::size_t kMaxExpertsPerSession = 32;
  static constexpr std::size_t kMaxScoredSessions = 1024;

  ScoreBook();  // checks the vessel judgements (CR) once

  // Throws ServiceError(kInvalidArgument) unless there are exactly as many
  // finite values in [0, 10] as the scene's scheme has indicators, and the
  // expert's name is at most 128 characters. The same expert scoring a
  // session again replaces the earlier sheet; a session scored under another
  // scene than before (a pushed scenario) starts a new sheet set. A new
  // expert beyond kMaxExpertsPerSession, or a new session beyond
  // kMaxScoredSessions, is kResourceExhausted.
  void Submit(const std::string& session_id, const std::string& scene, const std::string& expert,
              const std::vector<double>& indicators);
  // session_id empty: every scored session `visible` accepts (all when
  // visible is empty); otherwise just that one (kNotFound if unscored).
  ScoreReport Report(const std::string& session_id, const std::function<bool(const std::string&)>& visible = {}) const;
  bool Scored(const std::string& session_id) const;  // has at least one sheet

  // Told of every sheet Submit() accepted (to keep it in the results
  // database), on the submitting thread after the book's lock is released;
  // must not block. Set before any Submit().
  using SheetObserver = std::function<void(const std::string& session_id, const std::string& scene,
                                           const std::string& expert, const std::vector<double>& indicators)>;
  void SetObserver(SheetObserver observer) { observer_ = std::move(observer); }

  struct Summary {
    std::uint32_t experts = 0;
    double score = 0.0;
  };
  std::optional<Summary> SummaryOf(const std::string& session_id) const;  // nullopt: not scored

 private:
  struct Sheets {
    std::string scene;
    std::map<std::string, std::vector<double>> by_expert;
  };
  SessionScoreSheet Describe(const std::string& id, const Sheets& sheets) const;
  // Submit()'s part under the lock (the values already checked).
  void AddSheet(const std::string& session_id, const std::string& scene, const std::string& name,
                const std::vector<double>& indicators);

  Eigen::VectorXd vessel_weights_;  // global AHP weights (9)
  SheetObserver observer_;
  mutable std::mutex mutex_;
  std::map<std::string, Sheets> sheets_;
};

}  // namespace hapsim::service
