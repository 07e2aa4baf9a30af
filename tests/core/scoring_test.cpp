#include "hapsim/core/assessment/scoring.h"

#include <gtest/gtest.h>

#include <cmath>
#include <stdexcept>

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

// Paper Table 3 (subjective weight, one row shared by all five models):
//   soft tissue 0.17, force feedback 0.24, acupuncture effect 0.13,
//   training environment 0.10, real time 0.21, training effect 0.06,
//   system stability 0.09 — sums to exactly 1.00, so it is used as printed.
TEST(ComprehensiveScore, DelphiWeightsAreTheTable3Values) {
  Eigen::VectorXd table3(7);
  table3 << 0.17, 0.24, 0.13, 0.10, 0.21, 0.06, 0.09;
  EXPECT_LT((DelphiWeights() - table3).cwiseAbs().maxCoeff(), 1e-15);
}

// Paper Table 4 (objective weight beta per model, 3 decimals) and the
// reported average comprehensive scores (2 decimals):
//                 MSM    FEM    BEM    SHF    Ours
//   soft tissue   0.097  0.116  0.124  0.097  0.159
//   force fb      0.041  0.163  0.186  0.287  0.096
//   acup. effect  0.210  0.211  0.200  0.107  0.195
//   training env  0.204  0.023  0.058  0.148  0.116
//   real time     0.083  0.120  0.142  0.067  0.200
//   train effect  0.282  0.281  0.216  0.163  0.102
//   stability     0.084  0.087  0.073  0.132  0.133
//   column sum    1.001  1.001  0.999  1.001  1.001
//   avg score f   7.83   7.90   7.93   7.88   8.94
//
// What the paper's text does NOT contain: the raw 20-doctor x 7-indicator
// score matrices ("Appendix 3") and the per-doctor scores of Fig. 7 (a bar
// chart). So beta cannot be recomputed from the paper's data, and the
// averages f cannot be reproduced. What can be checked against the tables:
//  * Table 4 is consistent with eq. (12): each column sums to 1 within the
//    printed rounding (7 entries x 0.0005 = 0.0035; actual deviation 0.001).
//  * Feeding the implementation a 20-row matrix whose column deviations are
//    proportional to the printed beta (x_ij = avg + 3 beta_j z_i, z_i = +-1
//    alternating, so sigma_j = 3 beta_j by eq. 11) must give back Table 4:
//    the implementation returns beta_printed / column_sum, which differs from
//    the printed value by at most 0.287 * 0.001 / 0.999 = 0.00029, inside the
//    half-unit rounding of 0.0005 — tolerance 5e-4. (A variance-based beta
//    would come back proportional to beta^2 and fail by > 0.05.)
//  * Combined weights omega = 0.4 alpha + 0.6 beta from Tables 3 and 4, by
//    hand (0.4 alpha = 0.068 0.096 0.052 0.040 0.084 0.024 0.036), e.g. Ours:
//      0.068+0.6*0.159=0.1634  0.096+0.6*0.096=0.1536  0.052+0.6*0.195=0.1690
//      0.040+0.6*0.116=0.1096  0.084+0.6*0.200=0.2040  0.024+0.6*0.102=0.0852
//      0.036+0.6*0.133=0.1158
//    (other columns listed below). alpha is exact, beta carries +-0.0005, so
//    omega carries 0.6 * 0.0005 = 3e-4 — tolerance 3e-4. This pins mu = 0.4
//    on the subjective side (0.6 alpha + 0.4 beta misses by up to 0.05).
//  * With every column mean equal to the model's reported average, the mean
//    of f_i = sum_j omega_j x_ij must equal that average (sum omega = 1); this
//    only checks f's scale/normalisation, not the paper's unpublished data.
TEST(ComprehensiveScore, ReproducesPaperTable4ObjectiveAndCombinedWeights) {
  struct Model {
    const char* name;
    double beta[7];
    double omega[7];
    double average;
  };
  const Model models[] = {
      {"MSM", {0.097, 0.041, 0.210, 0.204, 0.083, 0.282, 0.084},
       {0.1262, 0.1206, 0.1780, 0.1624, 0.1338, 0.1932, 0.0864}, 7.83},
      {"FEM", {0.116, 0.163, 0.211, 0.023, 0.120, 0.281, 0.087},
       {0.1376, 0.1938, 0.1786, 0.0538, 0.1560, 0.1926, 0.0882}, 7.90},
      {"BEM", {0.124, 0.186, 0.200, 0.058, 0.142, 0.216, 0.073},
       {0.1424, 0.2076, 0.1720, 0.0748, 0.1692, 0.1536, 0.0798}, 7.93},
      {"SHF", {0.097, 0.287, 0.107, 0.148, 0.067, 0.163, 0.132},
       {0.1262, 0.2682, 0.1162, 0.1288, 0.1242, 0.1218, 0.1152}, 7.88},
      {"Ours", {0.159, 0.096, 0.195, 0.116, 0.200, 0.102, 0.133},
       {0.1634, 0.1536, 0.1690, 0.1096, 0.2040, 0.0852, 0.1158}, 8.94},
  };
  constexpr int kDoctors = 20;  // n = 20 in the paper
  for (const Model& m : models) {
    SCOPED_TRACE(m.name);
    const Eigen::Map<const Eigen::VectorXd> beta(m.beta, 7);
    const Eigen::Map<const Eigen::VectorXd> omega(m.omega, 7);
    EXPECT_NEAR(beta.sum(), 1.0, 7 * 0.0005);  // eq. (12) within rounding
    Eigen::MatrixXd x(kDoctors, 7);
    for (int i = 0; i < kDoctors; ++i) {
      const double z = (i % 2 == 0) ? 1.0 : -1.0;
      x.row(i) = (Eigen::VectorXd::Constant(7, m.average) + 3.0 * z * beta).transpose();
    }
    const auto r = ComprehensiveScores(x);
    EXPECT_LT((r.objective_weights - beta / beta.sum()).cwiseAbs().maxCoeff(), 1e-12);
    EXPECT_LT((r.objective_weights - beta).cwiseAbs().maxCoeff(), 5e-4);
    EXPECT_LT((r.combined_weights - omega).cwiseAbs().maxCoeff(), 3e-4);
    EXPECT_NEAR(r.scores.mean(), m.average, 1e-12);
  }
}

// Eq. (11) pinned with columns of different spread shapes (4 trainees).
// Column deviation patterns about the mean:
//   c1 = 5 + (5,-1,-1,-3) = (10,4,4,2): sigma^2 = (25+1+1+9)/4 = 9, sigma = 3,
//                                        MAD = (5+1+1+3)/4 = 2.5
//   c2 = 6 + (1,-1,1,-1)  = (7,5,7,5):   sigma = 1, var 1, MAD 1
//   c3 = 8 constant:                     0
//   c4 = 5 + (2,-2,2,-2)  = (7,3,7,3):   sigma = 2, var 4, MAD 2
//   c5 = 7 constant, c6 = 6 constant:    0
//   c7 = 5 + (4,-4,4,-4)  = (9,1,9,1):   sigma = 4, var 16, MAD 4
// eq. (11)/(12): sigma = (3,1,0,2,0,0,4), sum 10
//   beta = (0.3, 0.1, 0, 0.2, 0, 0, 0.4)
// (1/(n-1) instead of 1/n scales every sigma equally, so beta is unchanged.)
// Wrong alternatives:
//   variance: (9,1,0,4,0,0,16)/30  = (0.3, 0.0333, 0, 0.1333, 0, 0, 0.5333)
//   MAD:      (2.5,1,0,2,0,0,4)/9.5 = (0.2632, 0.1053, 0, 0.2105, 0, 0, 0.4211)
// omega = 0.4 alpha + 0.6 beta
//   = (0.068+0.18, 0.096+0.06, 0.052, 0.040+0.12, 0.084, 0.024, 0.036+0.24)
//   = (0.248, 0.156, 0.052, 0.160, 0.084, 0.024, 0.276), sum 1.000
// f_1 = (10,7,8,7,7,6,9):  2.480+1.092+0.416+1.120+0.588+0.144+2.484 = 8.324
// f_2 = (4,5,8,3,7,6,1):   0.992+0.780+0.416+0.480+0.588+0.144+0.276 = 3.676
// f_3 = (4,7,8,7,7,6,9):   0.992+1.092+0.416+1.120+0.588+0.144+2.484 = 6.836
// f_4 = (2,5,8,3,7,6,1):   0.496+0.780+0.416+0.480+0.588+0.144+0.276 = 3.180
TEST(ComprehensiveScore, ObjectiveWeightsUseStandardDeviationNotVarianceOrMad) {
  Eigen::MatrixXd x(4, 7);
  x << 10, 7, 8, 7, 7, 6, 9,
        4, 5, 8, 3, 7, 6, 1,
        4, 7, 8, 7, 7, 6, 9,
        2, 5, 8, 3, 7, 6, 1;
  const auto r = ComprehensiveScores(x);
  Eigen::VectorXd beta(7), omega(7), by_variance(7), by_mad(7);
  beta << 0.3, 0.1, 0.0, 0.2, 0.0, 0.0, 0.4;
  omega << 0.248, 0.156, 0.052, 0.160, 0.084, 0.024, 0.276;
  by_variance << 9, 1, 0, 4, 0, 0, 16;
  by_variance /= 30.0;
  by_mad << 2.5, 1, 0, 2, 0, 0, 4;
  by_mad /= 9.5;
  // The example really discriminates: the wrong definitions differ by > 0.03.
  ASSERT_GT((beta - by_variance).cwiseAbs().maxCoeff(), 0.03);
  ASSERT_GT((beta - by_mad).cwiseAbs().maxCoeff(), 0.03);
  EXPECT_LT((r.objective_weights - beta).cwiseAbs().maxCoeff(), 1e-12);
  EXPECT_LT((r.combined_weights - omega).cwiseAbs().maxCoeff(), 1e-12);
  ASSERT_EQ(r.scores.size(), 4);
  EXPECT_NEAR(r.scores[0], 8.324, 1e-12);
  EXPECT_NEAR(r.scores[1], 3.676, 1e-12);
  EXPECT_NEAR(r.scores[2], 6.836, 1e-12);
  EXPECT_NEAR(r.scores[3], 3.180, 1e-12);
  EXPECT_DOUBLE_EQ(r.mu, 0.4);
  // mu is the subjective share (eq. 13): mu = 1 -> alpha, mu = 0 -> beta.
  EXPECT_LT((ComprehensiveScores(x, 1.0).combined_weights - DelphiWeights()).cwiseAbs().maxCoeff(), 1e-15);
  EXPECT_LT((ComprehensiveScores(x, 0.0).combined_weights - beta).cwiseAbs().maxCoeff(), 1e-12);
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
