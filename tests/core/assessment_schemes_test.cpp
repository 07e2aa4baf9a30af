// The cutting paper's weighted residents' score and the vascular paper's
// analytic hierarchy process (acupuncture's Delphi + MSD: scoring_test.cpp).
#include <gtest/gtest.h>

#include <stdexcept>

#include "hapsim/core/assessment/ahp.h"
#include "hapsim/core/assessment/scoring.h"

namespace hapsim::core::assessment {
namespace {

// Cutting paper §4.3, Table 3: single-indicator means of 20 residents and
// the comprehensive score of each model, printed to 2 decimals (the means
// are whole numbers as printed). The weights are the text's Delphi weights.
// Tolerance 0.005: the printed scores' half-unit.
TEST(CuttingResidentsScore, ReproducesPaperTable3) {
  struct Model {
    const char* name;
    double means[7];
    double printed_score;
  };
  const Model models[] = {
      {"Ours", {10, 9, 9, 10, 9, 10, 9}, 9.43},
      {"Element deletion", {8, 8, 9, 8, 8, 8, 9}, 8.30},
      {"Node snapping", {8, 9, 7, 7, 9, 8, 9}, 7.96},
      {"Mesh subdivision", {9, 9, 9, 9, 10, 9, 9}, 9.10},
      {"Element duplication", {9, 8, 9, 9, 9, 9, 9}, 8.83},
  };
  for (const Model& m : models) {
    SCOPED_TRACE(m.name);
    EXPECT_NEAR(WeightedScore(CuttingDelphiWeights(), Eigen::Map<const Eigen::VectorXd>(m.means, 7)), m.printed_score,
                0.005);
  }
  EXPECT_NEAR(CuttingDelphiWeights().sum(), 1.0, 1e-12);
}

TEST(CuttingResidentsScore, RejectsMismatchedSizes) {
  EXPECT_THROW(WeightedScore(CuttingDelphiWeights(), Eigen::VectorXd::Zero(6)), std::invalid_argument);
}

// A perfectly consistent matrix a_ij = w_i / w_j has lambda_max = n, CR = 0
// and gives w back (to round-off).
TEST(Ahp, ConsistentMatrixRecoversItsWeights) {
  Eigen::VectorXd w(4);
  w << 0.4, 0.3, 0.2, 0.1;
  Eigen::MatrixXd a(4, 4);
  for (int i = 0; i < 4; ++i)
    for (int j = 0; j < 4; ++j) a(i, j) = w[i] / w[j];
  const auto r = AhpWeights(a);
  EXPECT_LT((r.weights - w).cwiseAbs().maxCoeff(), 1e-12);
  EXPECT_NEAR(r.lambda_max, 4.0, 1e-12);
  EXPECT_NEAR(r.consistency_ratio, 0.0, 1e-12);
}

// Reference values from numpy's eigen-solver (tests/core/ahp_reference.py);
// saaty3 is the textbook example (weights 0.637 0.258 0.105, CR 0.033).
// Tolerance 1e-9: two double-precision eigen-solvers on a 3x3/4x4 matrix.
TEST(Ahp, MatchesNumpyReference) {
  Eigen::MatrixXd saaty3(3, 3);
  saaty3 << 1, 3, 5, 1.0 / 3, 1, 3, 1.0 / 5, 1.0 / 3, 1;
  auto r = AhpWeights(saaty3);
  Eigen::Vector3d w3(0.636985571745, 0.258284994374, 0.104729433881);
  EXPECT_LT((r.weights - w3).cwiseAbs().maxCoeff(), 1e-9);
  EXPECT_NEAR(r.lambda_max, 3.038511090558, 1e-9);
  EXPECT_NEAR(r.consistency_ratio, 0.033199215998, 1e-9);

  Eigen::MatrixXd four(4, 4);
  four << 1, 2, 4, 3, 0.5, 1, 3, 2, 0.25, 1.0 / 3, 1, 0.5, 1.0 / 3, 0.5, 2, 1;
  r = AhpWeights(four);
  Eigen::Vector4d w4(0.467295982781, 0.277180590611, 0.095434951584, 0.160088475024);
  EXPECT_LT((r.weights - w4).cwiseAbs().maxCoeff(), 1e-9);
  EXPECT_NEAR(r.lambda_max, 4.030983498298, 1e-9);
  EXPECT_NEAR(r.consistency_ratio, 0.011475369740, 1e-9);
}

// 1 > 2 > 3 > 1, each by 5: CR = 2.76 (numpy), refused with the ratio named.
TEST(Ahp, RefusesInconsistentJudgements) {
  Eigen::MatrixXd cycle(3, 3);
  cycle << 1, 5, 0.2, 0.2, 1, 5, 5, 0.2, 1;
  try {
    AhpWeights(cycle);
    FAIL() << "an inconsistent matrix was accepted";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("CR = 2.758"), std::string::npos) << e.what();
  }
  // The limit is the caller's: with a looser one the same matrix passes.
  EXPECT_NEAR(AhpWeights(cycle, 3.0).consistency_ratio, 2.758620689655, 1e-9);
}

TEST(Ahp, RefusesMalformedMatrices) {
  EXPECT_THROW(AhpWeights(Eigen::MatrixXd::Ones(2, 3)), std::invalid_argument);   // not square
  EXPECT_THROW(AhpWeights(Eigen::MatrixXd::Ones(11, 11)), std::invalid_argument);  // beyond the RI table
  Eigen::MatrixXd not_reciprocal(2, 2);
  not_reciprocal << 1, 3, 3, 1;
  EXPECT_THROW(AhpWeights(not_reciprocal), std::invalid_argument);
  Eigen::MatrixXd negative(2, 2);
  negative << 1, -2, -0.5, 1;
  EXPECT_THROW(AhpWeights(negative), std::invalid_argument);
}

// Global weight = criterion weight x local weight: with consistent matrices
// from known weights the products are known exactly.
TEST(Ahp, HierarchyMultipliesCriterionAndLocalWeights) {
  auto consistent = [](const Eigen::Vector3d& w) {
    Eigen::MatrixXd a(3, 3);
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j) a(i, j) = w[i] / w[j];
    return a;
  };
  const Eigen::Vector3d criteria(0.2, 0.3, 0.5), visual(0.5, 0.25, 0.25), operational(0.6, 0.2, 0.2),
      tactile(0.2, 0.3, 0.5);
  const auto r = AhpHierarchy(consistent(criteria), {consistent(visual), consistent(operational), consistent(tactile)});
  ASSERT_EQ(r.global_weights.size(), 9);
  Eigen::VectorXd expected(9);
  expected << 0.10, 0.05, 0.05, 0.18, 0.06, 0.06, 0.10, 0.15, 0.25;
  EXPECT_LT((r.global_weights - expected).cwiseAbs().maxCoeff(), 1e-12);
  EXPECT_EQ(VesselIndicatorNames().size(), 9u);
  // A refused matrix is named by its place in the hierarchy.
  Eigen::MatrixXd cycle(3, 3);
  cycle << 1, 5, 0.2, 0.2, 1, 5, 5, 0.2, 1;
  try {
    AhpHierarchy(consistent(criteria), {consistent(visual), cycle, consistent(tactile)});
    FAIL();
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("criterion 2"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace hapsim::core::assessment
