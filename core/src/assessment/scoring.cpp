#include "hapsim/core/assessment/scoring.h"

#include <stdexcept>

#include "hapsim/core/math/eigen_blocking.h"

namespace hapsim::core::assessment {

Eigen::VectorXd DelphiWeights() {
  Eigen::VectorXd alpha(kIndicatorCount);
  alpha << 0.17, 0.24, 0.13, 0.10, 0.21, 0.06, 0.09;
  return alpha;
}

ComprehensiveScoreResult ComprehensiveScores(const Eigen::MatrixXd& x, double mu) {
  PinEigenBlockingSizes();  // a class's scores the same on every server
  if (x.cols() != kIndicatorCount) throw std::invalid_argument("scoring needs exactly 7 indicator columns");
  if (x.rows() == 0) throw std::invalid_argument("scoring needs at least one row of scores");
  if (!x.allFinite()) throw std::invalid_argument("indicator scores must be finite");
  if (!(mu >= 0.0 && mu <= 1.0)) throw std::invalid_argument("mu must be within [0, 1]");

  ComprehensiveScoreResult r;
  r.mu = mu;
  r.subjective_weights = DelphiWeights();
  const Eigen::RowVectorXd mean = x.colwise().mean();
  const Eigen::VectorXd sigma =
      ((x.rowwise() - mean).array().square().colwise().sum() / static_cast<double>(x.rows())).sqrt().transpose();
  const double total = sigma.sum();
  r.objective_weights = total > 0.0 ? Eigen::VectorXd(sigma / total) : r.subjective_weights;
  r.combined_weights = mu * r.subjective_weights + (1.0 - mu) * r.objective_weights;
  r.scores = x * r.combined_weights;
  return r;
}

Eigen::VectorXd CuttingDelphiWeights() {
  Eigen::VectorXd w(kIndicatorCount);
  w << 0.09, 0.17, 0.24, 0.13, 0.10, 0.21, 0.06;
  return w;
}

double WeightedScore(const Eigen::VectorXd& weights, const Eigen::VectorXd& x) {
  if (weights.size() != x.size()) throw std::invalid_argument("one weight per indicator score is needed");
  if (!weights.allFinite() || !x.allFinite()) throw std::invalid_argument("weights and scores must be finite");
  return weights.dot(x);
}

}  // namespace hapsim::core::assessment
