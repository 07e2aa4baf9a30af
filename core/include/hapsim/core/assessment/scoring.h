// Comprehensive weighted score of the acupuncture paper §4.2: experts score
// 7 indicators (soft tissue material, force feedback, acupuncture effect,
// training environment, real time, training effect, system stability) 0..10.
//   subjective (Delphi) weights  alpha_j (fixed, sum 1)
//   objective weights            beta_j = sigma_j / sum_k sigma_k,
//                                sigma_j = sqrt(1/n sum_i (x_ij - E_j)^2)  (population std over the class)
//   combined                     w_j = mu alpha_j + (1 - mu) beta_j,  mu = 0.4
//   score of sample i            f_i = sum_j w_j x_ij
// The paper's samples i are the raters (20 doctors) of one system, so each
// system gets its own objective weights (its Table 4 has one column per
// model): call this with one row per rater of one session, and a trainee's
// score depends on their raters only, never on other trainees.
// [decide] When every indicator has zero spread (one session, or identical
// scores) beta is 0/0; the spread then carries no information, so beta = alpha
// and the weights reduce to the Delphi ones.
#pragma once
#include <Eigen/Core>

namespace hapsim::core::assessment {

inline constexpr int kIndicatorCount = 7;

// The paper's Delphi weights, in the indicator order above.
Eigen::VectorXd DelphiWeights();

struct ComprehensiveScoreResult {
  Eigen::VectorXd subjective_weights;  // alpha (7)
  Eigen::VectorXd objective_weights;   // beta (7)
  Eigen::VectorXd combined_weights;    // w (7)
  double mu = 0.4;
  Eigen::VectorXd scores;              // f (n), one per row of the input
};

// x: n x 7 indicator scores (rows: the raters of one session). Throws
// std::invalid_argument if x does not have 7 columns, has no rows, has a
// non-finite entry, or mu is outside [0, 1].
ComprehensiveScoreResult ComprehensiveScores(const Eigen::MatrixXd& x, double mu = 0.4);

// The cutting paper's §4.3 practical evaluation: residents score 7
// indicators (tissue texture, force feedback, cutting effect, incision
// shape, real-time performance, training effectiveness, system stability)
// 0..10, and a system's comprehensive score is sum_j w_j mean_j with the
// Delphi weights it lists (0.09, 0.17, 0.24, 0.13, 0.10, 0.21, 0.06) — no
// objective part.
Eigen::VectorXd CuttingDelphiWeights();
// sum_j weights_j x_j. Throws std::invalid_argument if the sizes differ or
// anything is not finite.
double WeightedScore(const Eigen::VectorXd& weights, const Eigen::VectorXd& x);

}  // namespace hapsim::core::assessment
