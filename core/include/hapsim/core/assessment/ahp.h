// Analytic hierarchy process (Saaty), as the vascular paper §3.3 uses it to
// weight its nine force-tactile indicators: doctors fill pairwise comparison
// matrices on the 1-9 ratio scale (a_ij = how much more indicator i matters
// than j, a_ji = 1/a_ij); the weights are the principal eigenvector,
// normalised to sum 1, and the matrix is accepted only when it is consistent
// enough:
//   lambda_max  principal eigenvalue (>= n; = n for a perfectly consistent matrix)
//   CI = (lambda_max - n) / (n - 1)
//   CR = CI / RI(n),  RI = Saaty's random index (0, 0, 0.58, 0.90, 1.12, 1.24, 1.32, 1.41, 1.45, 1.49)
//   refused when CR > 0.1
// The paper's hierarchy: target -> 3 criteria (visual, operational, tactile)
// -> 9 indicators, 3 per criterion; an indicator's global weight is its
// criterion's weight times its weight within the criterion, and the
// comprehensive score is G = sum_k w_k x_k (its eq. 40).
#pragma once
#include <string>
#include <vector>

#include <Eigen/Core>

namespace hapsim::core::assessment {

inline constexpr double kMaxConsistencyRatio = 0.1;

struct AhpResult {
  Eigen::VectorXd weights;  // principal eigenvector, sum 1, all > 0
  double lambda_max = 0.0;
  double consistency_index = 0.0;  // CI
  double consistency_ratio = 0.0;  // CR (0 for n <= 2, which are always consistent)
};

// Saaty's random consistency index for an n x n matrix, n in [1, 10].
double RandomIndex(int n);

// Weights of one pairwise comparison matrix. Throws std::invalid_argument
// (with the reason in words) unless the matrix is square, 1..10 wide,
// finite, positive, has a unit diagonal and is reciprocal (a_ji = 1/a_ij to
// 1e-6 relative), or when CR > max_cr.
AhpResult AhpWeights(const Eigen::MatrixXd& pairwise, double max_cr = kMaxConsistencyRatio);

// A two-level hierarchy: one criteria matrix and one indicator matrix per
// criterion. Global weights list the indicators criterion by criterion.
struct AhpHierarchyResult {
  AhpResult criteria;
  std::vector<AhpResult> indicators;  // one per criterion
  Eigen::VectorXd global_weights;     // sum 1
};
// Throws std::invalid_argument if the count of indicator matrices is not the
// criteria matrix's size, or any matrix is refused (its index is named).
AhpHierarchyResult AhpHierarchy(const Eigen::MatrixXd& criteria, const std::vector<Eigen::MatrixXd>& indicators,
                                double max_cr = kMaxConsistencyRatio);

// The vascular paper's indicators, in the hierarchy's order.
const std::vector<std::string>& VesselIndicatorNames();  // 9: image fluency, ..., feedback authenticity
const std::vector<std::string>& VesselCriterionNames();  // 3: visual, operational, tactile

// hapsim's default judgements for the vessel hierarchy (criteria first, then
// one matrix per criterion), used until a class brings its doctors' own. NOT
// the paper's: its Table 1 is an image absent from the text. They rank
// tactile > operational > visual (1/2, 1/3, 1/2 steps) — a force-feedback
// trainer's priorities — and pass the CR check (docs/classroom.md).
struct AhpJudgements {
  Eigen::MatrixXd criteria;
  std::vector<Eigen::MatrixXd> indicators;
};
AhpJudgements DefaultVesselJudgements();

}  // namespace hapsim::core::assessment
