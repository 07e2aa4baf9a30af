#include "hapsim/core/msm/stability.h"

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <vector>

#include "hapsim/core/msm/particle_steppers.h"

namespace hapsim::core {

namespace {

// Block Gershgorin (Feingold-Varga) on M^-1/2 K M^-1/2: every eigenvalue
// is <= max_i [ lambda_max(K_ii)/m_i + sum_j |K_ij|/sqrt(m_i m_j) ], and a
// spring's 3x3 block near rest has norm <= k. The rows are kept scaled by
// m_i (divided at the end), per node.
struct MsmGershgorinRows {
  std::vector<double> k_row, c_row;
  // Absolute dampers (node and anchor) damp every mode; spring dampers only
  // relative motion, so only the absolute ones give a lower bound.
  std::vector<double> c_absolute;
};

// EstimateModeBounds's steps, in order.

// The extra stiffness and damping every node may carry, and node damping.
MsmGershgorinRows StartMsmGershgorinRows(const MsmModel& m, double extra_k, double extra_c) {
  const auto n = static_cast<std::size_t>(m.num_nodes);
  MsmGershgorinRows rows{std::vector<double>(n, extra_k), std::vector<double>(n, 0.0), std::vector<double>(n, 0.0)};
  for (std::size_t i = 0; i < n; ++i) {
    rows.c_absolute[i] = m.node_damping_Ns_per_m[static_cast<Eigen::Index>(i)];
    rows.c_row[i] = extra_c + rows.c_absolute[i];
  }
  return rows;
}

void AddMsmSpringRows(const MsmModel& m, MsmGershgorinRows& rows) {
  for (std::int32_t s = 0; s < m.NumSprings(); ++s) {
    const auto i = static_cast<std::size_t>(m.spring_i[static_cast<std::size_t>(s)]);
    const auto j = static_cast<std::size_t>(m.spring_j[static_cast<std::size_t>(s)]);
    const double mi = m.mass_kg[static_cast<Eigen::Index>(i)], mj = m.mass_kg[static_cast<Eigen::Index>(j)];
    const double off = 1.0 / std::sqrt(mi * mj);
    const double k = m.spring_k_N_per_m[static_cast<std::size_t>(s)];
    const double c = m.spring_c_Ns_per_m[static_cast<std::size_t>(s)];
    // row_i / m_i = k/m_i + k/sqrt(m_i m_j).
    rows.k_row[i] += k * (1.0 + mi * off);
    rows.k_row[j] += k * (1.0 + mj * off);
    rows.c_row[i] += c * (1.0 + mi * off);
    rows.c_row[j] += c * (1.0 + mj * off);
  }
}

void AddMsmAnchorRows(const MsmModel& m, MsmGershgorinRows& rows) {
  for (std::int32_t a = 0; a < m.NumAnchors(); ++a) {
    const auto i = static_cast<std::size_t>(m.anchor_node[static_cast<std::size_t>(a)]);
    rows.k_row[i] += m.anchor_k_N_per_m[static_cast<std::size_t>(a)];
    rows.c_row[i] += m.anchor_c_Ns_per_m[static_cast<std::size_t>(a)];
    rows.c_absolute[i] += m.anchor_c_Ns_per_m[static_cast<std::size_t>(a)];
  }
}

// The bounds over the free nodes, each row divided by its node's mass.
ModeBounds MsmModeBoundsFromRows(const MsmModel& m, const MsmGershgorinRows& rows) {
  ModeBounds b;
  b.gamma_min_per_s = std::numeric_limits<double>::infinity();
  for (std::size_t i = 0; i < static_cast<std::size_t>(m.num_nodes); ++i) {
    if (m.fixed[i]) continue;
    const double mi = m.mass_kg[static_cast<Eigen::Index>(i)];
    b.omega2_max_per_s2 = std::max(b.omega2_max_per_s2, rows.k_row[i] / mi);
    b.gamma_max_per_s = std::max(b.gamma_max_per_s, rows.c_row[i] / mi);
    b.gamma_min_per_s = std::min(b.gamma_min_per_s, rows.c_absolute[i] / mi);
  }
  if (!std::isfinite(b.gamma_min_per_s)) b.gamma_min_per_s = 0.0;
  return b;
}

}  // namespace

ModeBounds EstimateModeBounds(const MsmModel& m, double extra_k, double extra_c) {
  MsmGershgorinRows rows = StartMsmGershgorinRows(m, extra_k, extra_c);
  AddMsmSpringRows(m, rows);
  AddMsmAnchorRows(m, rows);
  return MsmModeBoundsFromRows(m, rows);
}

double AmplificationRadius(IntegratorChoice method, double omega2, double gamma, double h) {
  // Columns = one step applied to the unit states (x, v) = (1, 0) and (0, 1).
  const LinearParticle p{1.0, omega2, gamma};
  Eigen::Matrix2d A;
  for (int col = 0; col < 2; ++col) {
    double x = col == 0 ? 1.0 : 0.0, v = col == 1 ? 1.0 : 0.0;
    StepParticle(p, method, h, x, v);
    A(0, col) = x;
    A(1, col) = v;
  }
  return A.eigenvalues().cwiseAbs().maxCoeff();
}

double CriticalTimeStep_s(const ModeBounds& b, IntegratorChoice method) {
  if (method.kind == IntegratorKind::kBackwardEuler) return std::numeric_limits<double>::infinity();
  if (b.omega2_max_per_s2 <= 0.0 && b.gamma_max_per_s <= 0.0)
    return std::numeric_limits<double>::infinity();
  // Sampled modes: w^2 over [0, w_max^2], damping at both bounds.
  constexpr int kOmegaSamples = 33;
  constexpr double kSlack = 1e-12;  // rho = 1 exactly (undamped, neutral) counts as stable
  auto stable = [&](double h) {
    for (int a = 0; a < kOmegaSamples; ++a) {
      const double w2 = b.omega2_max_per_s2 * a / (kOmegaSamples - 1);
      for (const double g : {b.gamma_min_per_s, b.gamma_max_per_s}) {
        if (AmplificationRadius(method, w2, g, h) > 1.0 + kSlack) return false;
      }
    }
    return true;
  };
  // Upper bracket: no explicit scheme here is stable past h w = 3 or h g = 3.
  const double scale = std::max(std::sqrt(b.omega2_max_per_s2), b.gamma_max_per_s);
  double lo = 0.0, hi = 4.0 / scale;
  if (stable(hi)) return hi;
  // Find the first stable h going down (the region starts at h -> 0 unless
  // the scheme is unstable for every h, e.g. explicit Euler with g_min = 0).
  double probe = hi;
  for (int k = 0; k < 60 && !stable(probe); ++k) probe *= 0.5;
  if (!stable(probe)) return 0.0;
  lo = probe;
  hi = std::min(hi, 2.0 * probe);
  for (int k = 0; k < 60; ++k) {
    const double mid = 0.5 * (lo + hi);
    (stable(mid) ? lo : hi) = mid;
  }
  return lo;
}

}  // namespace hapsim::core
