#include "hapsim/core/assessment/ahp.h"

#include <Eigen/Eigenvalues>
#include <cmath>
#include <stdexcept>

#include "hapsim/core/math/eigen_blocking.h"

namespace hapsim::core::assessment {

double RandomIndex(int n) {
  // Saaty (1980), the values every AHP text tabulates for n = 1..10.
  static constexpr double kRi[] = {0.0, 0.0, 0.58, 0.90, 1.12, 1.24, 1.32, 1.41, 1.45, 1.49};
  if (n < 1 || n > 10) throw std::invalid_argument("AHP random index is tabulated for 1..10 criteria");
  return kRi[n - 1];
}

AhpResult AhpWeights(const Eigen::MatrixXd& a, double max_cr) {
  PinEigenBlockingSizes();  // the weights the same on every server
  const auto n = a.rows();
  if (n != a.cols()) throw std::invalid_argument("a pairwise comparison matrix must be square");
  if (n < 1 || n > 10) throw std::invalid_argument("a pairwise comparison matrix must be 1..10 wide");
  if (!a.allFinite() || (a.array() <= 0.0).any()) {
    throw std::invalid_argument("pairwise comparisons must be finite and positive");
  }
  for (Eigen::Index i = 0; i < n; ++i) {
    if (std::abs(a(i, i) - 1.0) > 1e-9) throw std::invalid_argument("a pairwise comparison matrix has 1 on its diagonal");
    for (Eigen::Index j = i + 1; j < n; ++j) {
      if (std::abs(a(i, j) * a(j, i) - 1.0) > 1e-6) {
        throw std::invalid_argument("pairwise comparisons must be reciprocal: a(" + std::to_string(i + 1) + "," +
                                    std::to_string(j + 1) + ") * a(" + std::to_string(j + 1) + "," +
                                    std::to_string(i + 1) + ") != 1");
      }
    }
  }
  // Perron root of a positive matrix: the eigenvalue of largest real part is
  // real and simple, and its eigenvector can be taken positive.
  Eigen::EigenSolver<Eigen::MatrixXd> solver(a);
  Eigen::Index best = 0;
  for (Eigen::Index k = 1; k < n; ++k) {
    if (solver.eigenvalues()[k].real() > solver.eigenvalues()[best].real()) best = k;
  }
  Eigen::VectorXd v = solver.eigenvectors().col(best).real();
  if (v.sum() < 0.0) v = -v;
  AhpResult r;
  r.weights = v / v.sum();
  r.lambda_max = solver.eigenvalues()[best].real();
  r.consistency_index = n > 1 ? (r.lambda_max - static_cast<double>(n)) / static_cast<double>(n - 1) : 0.0;
  const double ri = RandomIndex(static_cast<int>(n));
  r.consistency_ratio = ri > 0.0 ? r.consistency_index / ri : 0.0;
  if (r.consistency_ratio > max_cr) {
    throw std::invalid_argument("pairwise comparisons are inconsistent: CR = " + std::to_string(r.consistency_ratio) +
                                " > " + std::to_string(max_cr) + " (revise the judgements)");
  }
  return r;
}

AhpHierarchyResult AhpHierarchy(const Eigen::MatrixXd& criteria, const std::vector<Eigen::MatrixXd>& indicators,
                                double max_cr) {
  AhpHierarchyResult r;
  try {
    r.criteria = AhpWeights(criteria, max_cr);
  } catch (const std::invalid_argument& e) {
    throw std::invalid_argument(std::string("criteria matrix: ") + e.what());
  }
  if (static_cast<Eigen::Index>(indicators.size()) != criteria.rows()) {
    throw std::invalid_argument("one indicator matrix per criterion is needed: " + std::to_string(criteria.rows()) +
                                " criteria, " + std::to_string(indicators.size()) + " matrices");
  }
  Eigen::Index total = 0;
  for (std::size_t c = 0; c < indicators.size(); ++c) {
    try {
      r.indicators.push_back(AhpWeights(indicators[c], max_cr));
    } catch (const std::invalid_argument& e) {
      throw std::invalid_argument("indicator matrix of criterion " + std::to_string(c + 1) + ": " + e.what());
    }
    total += indicators[c].rows();
  }
  r.global_weights.resize(total);
  Eigen::Index k = 0;
  for (std::size_t c = 0; c < indicators.size(); ++c) {
    const auto& local = r.indicators[c].weights;
    r.global_weights.segment(k, local.size()) = r.criteria.weights[static_cast<Eigen::Index>(c)] * local;
    k += local.size();
  }
  return r;
}

AhpJudgements DefaultVesselJudgements() {
  AhpJudgements j;
  j.criteria.resize(3, 3);
  j.criteria << 1, 1.0 / 2, 1.0 / 3,  //
      2, 1, 1.0 / 2,                  //
      3, 2, 1;                        // visual < operational < tactile
  Eigen::MatrixXd visual(3, 3), operational(3, 3), tactile(3, 3);
  visual << 1, 1, 1.0 / 2, 1, 1, 1.0 / 2, 2, 2, 1;                  // update real-time counts double
  operational << 1, 1.0 / 2, 1.0 / 2, 2, 1, 1, 2, 1, 1;             // naturalness, stability over texture
  tactile << 1, 1.0 / 2, 1, 2, 1, 2, 1, 1.0 / 2, 1;                 // haptic feedback counts double
  j.indicators = {visual, operational, tactile};
  return j;
}

const std::vector<std::string>& VesselCriterionNames() {
  static const std::vector<std::string> kNames = {"visual", "operational", "tactile"};
  return kNames;
}

const std::vector<std::string>& VesselIndicatorNames() {
  // Fig. 13 of the vascular paper, grouped under the criteria above.
  static const std::vector<std::string> kNames = {
      "image fluency",         "visual refresh rate",   "update real-time",
      "texture",               "interaction naturalness", "system stability",
      "deformation accuracy",  "haptic feedback",       "feedback authenticity"};
  return kNames;
}

}  // namespace hapsim::core::assessment
