#include "hapsim/core/pbd/xpbd.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <stdexcept>
#include <string>

namespace hapsim::core {

namespace {

// BuildXpbdModel's steps, in order (the first bad field is the one reported).

void CheckXpbdDef(const XpbdDef& def) {
  const auto n = static_cast<std::size_t>(def.x0_m.cols());
  if (n == 0) throw std::invalid_argument("xpbd: no nodes");
  if (def.mass_kg.size() != n || (!def.fixed.empty() && def.fixed.size() != n)) {
    throw std::invalid_argument("xpbd: mass and fixed need one entry per node");
  }
  if (!def.x0_m.allFinite() || !def.gravity_W_m_per_s2.allFinite()) {
    throw std::invalid_argument("xpbd: positions and gravity must be finite");
  }
  if (def.iterations < 1 || def.iterations > 1000) throw std::invalid_argument("xpbd: iterations must be in [1, 1000]");
  if (!(def.damping_per_s >= 0.0) || !std::isfinite(def.damping_per_s)) {
    throw std::invalid_argument("xpbd: damping must be >= 0");
  }
  if (!(def.plain_pbd_stiffness >= 0.0 && def.plain_pbd_stiffness <= 1.0)) {
    throw std::invalid_argument("xpbd: plain PBD stiffness must be in [0, 1]");
  }
}

// 1 / mass per node, 0 for a fixed node.
Eigen::VectorXd XpbdInverseMasses(const XpbdDef& def) {
  const auto n = static_cast<std::size_t>(def.x0_m.cols());
  Eigen::VectorXd inv_mass_per_kg(static_cast<Eigen::Index>(n));
  for (std::size_t i = 0; i < n; ++i) {
    if (!(def.mass_kg[i] > 0.0) || !std::isfinite(def.mass_kg[i])) {
      throw std::invalid_argument("xpbd: node " + std::to_string(i) + " needs a positive mass");
    }
    const bool held = !def.fixed.empty() && def.fixed[i];
    inv_mass_per_kg[static_cast<Eigen::Index>(i)] = held ? 0.0 : 1.0 / def.mass_kg[i];
  }
  return inv_mass_per_kg;
}

void CheckXpbdDistanceConstraints(const XpbdDef& def, std::int32_t n) {
  for (std::size_t c = 0; c < def.distance.size(); ++c) {
    const auto& d = def.distance[c];
    if (d.i < 0 || d.j < 0 || d.i >= n || d.j >= n || d.i == d.j) {
      throw std::invalid_argument("xpbd: distance constraint " + std::to_string(c) + " names a missing node");
    }
    if (!(d.rest_m >= 0.0) || !(d.compliance_m_per_N >= 0.0) || !std::isfinite(d.rest_m) ||
        !std::isfinite(d.compliance_m_per_N)) {
      throw std::invalid_argument("xpbd: distance constraint " + std::to_string(c) +
                                  " needs a finite rest length and compliance >= 0");
    }
  }
}

}  // namespace

XpbdModel BuildXpbdModel(const XpbdDef& def) {
  CheckXpbdDef(def);
  XpbdModel m;
  m.n = static_cast<std::int32_t>(def.x0_m.cols());
  m.x0_m = def.x0_m;
  m.inv_mass_per_kg = XpbdInverseMasses(def);
  CheckXpbdDistanceConstraints(def, m.n);
  m.distance = def.distance;
  m.gravity_W_m_per_s2 = def.gravity_W_m_per_s2;
  m.iterations = def.iterations;
  m.damping_per_s = def.damping_per_s;
  m.plain_pbd_stiffness = def.plain_pbd_stiffness;
  return m;
}

XpbdState MakeXpbdState(const XpbdModel& model) {
  XpbdState s;
  s.x_m = model.x0_m;
  s.v_m_per_s = Eigen::Matrix3Xd::Zero(3, model.n);
  s.f_ext_N = Eigen::Matrix3Xd::Zero(3, model.n);
  s.x_start_m = model.x0_m;
  s.lambda = Eigen::VectorXd::Zero(static_cast<Eigen::Index>(model.distance.size()));
  return s;
}

void StepXpbd(const XpbdModel& model, XpbdState& s, double h_s, XpbdExtraConstraints* extra) {
  const double decay = std::max(0.0, 1.0 - model.damping_per_s * h_s);
  s.x_start_m = s.x_m;
  for (std::int32_t i = 0; i < model.n; ++i) {
    const double w = model.inv_mass_per_kg[i];
    if (w == 0.0) continue;
    s.v_m_per_s.col(i) = decay * s.v_m_per_s.col(i) + h_s * (model.gravity_W_m_per_s2 + w * s.f_ext_N.col(i));
    s.x_m.col(i) += h_s * s.v_m_per_s.col(i);
  }
  s.lambda.setZero();
  if (extra) extra->BeginStep();
  const bool plain = model.plain_pbd_stiffness > 0.0;
  for (int it = 0; it < model.iterations; ++it) {
    for (std::size_t c = 0; c < model.distance.size(); ++c) {
      const DistanceConstraint& d = model.distance[c];
      const double wi = model.inv_mass_per_kg[d.i], wj = model.inv_mass_per_kg[d.j];
      if (plain) {
        ProjectDistancePlainPbd(s.x_m, d.i, d.j, wi, wj, d.rest_m, model.plain_pbd_stiffness);
        continue;
      }
      Eigen::Vector3d move_j = Eigen::Vector3d::Zero();
      ProjectDistanceXpbd(s.x_m, d.i, s.x_m.col(d.j), wi, wj, d.rest_m, d.compliance_m_per_N / (h_s * h_s),
                          &s.lambda[static_cast<Eigen::Index>(c)], false, &move_j);
      s.x_m.col(d.j) += move_j;
    }
    if (extra) extra->Project(s.x_m, model.inv_mass_per_kg, h_s);
  }
  s.v_m_per_s = (s.x_m - s.x_start_m) / h_s;
  s.time_s += h_s;
}

double TetSpringEnergy_J(const TetEnergyConstraint& tet, const Eigen::Matrix3Xd& x_m) {
  double U = 0.0;
  for (std::size_t e = 0; e < 6; ++e) {
    const auto [a, b] = kTetEdges[e];
    const double stretch = (x_m.col(tet.node[static_cast<std::size_t>(a)]) - x_m.col(tet.node[static_cast<std::size_t>(b)])).norm() -
                           tet.rest_m[e];
    U += 0.5 * tet.k_N_per_m[e] * stretch * stretch;
  }
  return U;
}

void ProjectTetEnergyXpbd(Eigen::Matrix3Xd& x_m, const TetEnergyConstraint& tet, const Eigen::VectorXd& inv_mass_per_kg,
                          double h_s, double* lambda) {
  // grad U per node, then C = sqrt(2U), grad C = grad U / C.
  std::array<Eigen::Vector3d, 4> grad;
  grad.fill(Eigen::Vector3d::Zero());
  double U = 0.0;
  for (std::size_t e = 0; e < 6; ++e) {
    const auto [a, b] = kTetEdges[e];
    const Eigen::Vector3d d = x_m.col(tet.node[static_cast<std::size_t>(a)]) - x_m.col(tet.node[static_cast<std::size_t>(b)]);
    const double length = d.norm();
    if (length < 1e-15) return;  // a collapsed edge has no direction
    const double stretch = length - tet.rest_m[e];
    U += 0.5 * tet.k_N_per_m[e] * stretch * stretch;
    const Eigen::Vector3d g = tet.k_N_per_m[e] * stretch * d / length;
    grad[static_cast<std::size_t>(a)] += g;
    grad[static_cast<std::size_t>(b)] -= g;
  }
  if (U <= 1e-300) return;
  const double C = std::sqrt(2.0 * U);
  double denominator = 1.0 / (h_s * h_s);  // α̃ with unit compliance
  for (std::size_t v = 0; v < 4; ++v) denominator += inv_mass_per_kg[tet.node[v]] * grad[v].squaredNorm() / (C * C);
  const double dlambda = (-C - *lambda / (h_s * h_s)) / denominator;
  *lambda += dlambda;
  for (std::size_t v = 0; v < 4; ++v) x_m.col(tet.node[v]) += inv_mass_per_kg[tet.node[v]] * dlambda * grad[v] / C;
}

TetEnergyConstraint MakeTetEnergyConstraint(const Eigen::Matrix3Xd& x0_m, std::array<std::int32_t, 4> nodes,
                                            double stiffness_N_per_m) {
  TetEnergyConstraint t;
  t.node = nodes;
  for (std::size_t e = 0; e < 6; ++e) {
    const auto [a, b] = kTetEdges[e];
    t.rest_m[e] = (x0_m.col(nodes[static_cast<std::size_t>(a)]) - x0_m.col(nodes[static_cast<std::size_t>(b)])).norm();
    t.k_N_per_m[e] = stiffness_N_per_m;
  }
  return t;
}

double DistanceConstraintForce_N(const XpbdState& state, std::size_t constraint, double h_s) {
  return state.lambda[static_cast<Eigen::Index>(constraint)] / (h_s * h_s);
}

int OrderByColour(std::vector<DistanceConstraint>& constraints, std::int32_t n_nodes) {
  // Colours used at each node so far, as bits; a node of degree > 64 is not
  // a lattice (it then shares the last colour, which only costs overlap).
  std::vector<std::uint64_t> used(static_cast<std::size_t>(std::max(n_nodes, 0)), 0);
  std::vector<int> colour(constraints.size(), 0);
  int colours = 0;
  for (const DistanceConstraint& d : constraints) {
    if (d.i < 0 || d.j < 0 || d.i >= n_nodes || d.j >= n_nodes) {
      throw std::invalid_argument("xpbd: a constraint names node " + std::to_string(std::max(d.i, d.j)) +
                                  " or " + std::to_string(std::min(d.i, d.j)) + ", outside 0.." +
                                  std::to_string(n_nodes - 1));
    }
  }
  for (std::size_t c = 0; c < constraints.size(); ++c) {
    const std::uint64_t taken = used[static_cast<std::size_t>(constraints[c].i)] |
                                used[static_cast<std::size_t>(constraints[c].j)];
    int k = 0;
    while (k < 63 && (taken >> k) & 1u) ++k;
    colour[c] = k;
    used[static_cast<std::size_t>(constraints[c].i)] |= std::uint64_t{1} << k;
    used[static_cast<std::size_t>(constraints[c].j)] |= std::uint64_t{1} << k;
    colours = std::max(colours, k + 1);
  }
  std::vector<std::size_t> order(constraints.size());
  for (std::size_t c = 0; c < order.size(); ++c) order[c] = c;
  std::stable_sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) { return colour[a] < colour[b]; });
  std::vector<DistanceConstraint> sorted;
  sorted.reserve(constraints.size());
  for (const std::size_t c : order) sorted.push_back(constraints[c]);
  constraints = std::move(sorted);
  return colours;
}

}  // namespace hapsim::core
