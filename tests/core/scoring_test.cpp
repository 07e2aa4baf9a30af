#include "hapsim/core/assessment/scoring.h"

#include <gtest/gtest.h>

namespace hapsim::core::assessment {
namespace {

// Hand-computed example, two trainees:
//   A = (8, 6, 7, 9, 5, 8, 7), B = (6, 6, 9, 9, 7, 8, 5)
//   sigma_j = |A_j - B_j| / 2 = (1, 0, 1, 0, 1, 0, 1), sum 4
//   beta = (0.25, 0, 0.25, 0, 0.25, 0, 0.25)
//   w = 0.4 alpha + 0.6 beta
//     = (0.218, 0.096, 0.202, 0.040, 0.234, 0.024, 0.186)
TEST(ComprehensiveScore, MatchesHandComputedTwoTraineeExample) {
  Eigen::MatrixXd x(2, 7);
  x << 8, 6, 7, 9, 5, 8, 7,
       6, 6, 9, 9, 7, 8, 5;
  const auto r = ComprehensiveScores(x);
  Eigen::VectorXd w(7);
  w << 0.218, 0.096, 0.202, 0.040, 0.234, 0.024, 0.186;
  EXPECT_LT((r.combined_weights - w).cwiseAbs().maxCoeff(), 1e-12);
  // f_A = 1.744 + 0.576 + 1.414 + 0.360 + 1.170 + 0.192 + 1.302 = 6.758
  // f_B = 1.308 + 0.576 + 1.818 + 0.360 + 1.638 + 0.192 + 0.930 = 6.822
  EXPECT_NEAR(r.scores[0], 6.758, 1e-12);
  EXPECT_NEAR(r.scores[1], 6.822, 1e-12);
  EXPECT_NEAR(r.combined_weights.sum(), 1.0, 1e-12);
}

TEST(ComprehensiveScore, DelphiWeightsSumToOne) { EXPECT_NEAR(DelphiWeights().sum(), 1.0, 1e-12); }

TEST(ComprehensiveScore, NoSpreadFallsBackToDelphiWeights) {
  Eigen::MatrixXd x(1, 7);
  x << 5, 5, 5, 5, 5, 5, 5;
  const auto r = ComprehensiveScores(x);
  EXPECT_LT((r.combined_weights - DelphiWeights()).cwiseAbs().maxCoeff(), 1e-15);
  EXPECT_NEAR(r.scores[0], 5.0, 1e-12);
}

TEST(ComprehensiveScore, RejectsWrongShapeAndNonFinite) {
  EXPECT_THROW(ComprehensiveScores(Eigen::MatrixXd::Zero(2, 6)), std::invalid_argument);
  EXPECT_THROW(ComprehensiveScores(Eigen::MatrixXd::Zero(0, 7)), std::invalid_argument);
  Eigen::MatrixXd bad = Eigen::MatrixXd::Zero(1, 7);
  bad(0, 3) = std::nan("");
  EXPECT_THROW(ComprehensiveScores(bad), std::invalid_argument);
}

}  // namespace
}  // namespace hapsim::core::assessment
