#include "hapsim/core/msm/msm_model.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

namespace hapsim::core {
namespace {

[[noreturn]] void Fail(const std::string& what) {
  throw std::invalid_argument("BuildMsmModel: " + what);
}

void CheckSize(std::size_t got, std::size_t want, const char* field, bool may_be_empty) {
  if (may_be_empty && got == 0) return;
  if (got != want)
    Fail(std::string(field) + " has " + std::to_string(got) + " entries, expected " +
         std::to_string(want));
}

void CheckCoefficient(double value, const char* field, std::size_t index) {
  if (!std::isfinite(value) || value < 0.0)
    Fail(std::string(field) + "[" + std::to_string(index) + "] = " + std::to_string(value) +
         " must be finite and >= 0");
}

// BuildMsmModel's steps, in the order it validates (the first bad field is
// the one reported).

// Node arrays: sizes, positions, masses and damping.
void CopyMsmNodes(const MsmDef& def, MsmModel& m) {
  const auto n = static_cast<std::size_t>(def.x0_m.cols());
  if (n == 0) Fail("x0_m has no nodes");
  if (!def.x0_m.allFinite()) Fail("x0_m contains NaN/inf");
  CheckSize(static_cast<std::size_t>(def.mass_kg.size()), n, "mass_kg", false);
  CheckSize(def.fixed.size(), n, "fixed", true);
  CheckSize(static_cast<std::size_t>(def.node_damping_Ns_per_m.size()), n,
            "node_damping_Ns_per_m", true);
  if (!def.gravity_m_per_s2.allFinite()) Fail("gravity_m_per_s2 contains NaN/inf");

  m.num_nodes = static_cast<std::int32_t>(n);
  m.x0_m = def.x0_m;
  m.mass_kg = def.mass_kg;
  m.fixed = def.fixed.empty() ? std::vector<std::uint8_t>(n, 0) : def.fixed;
  m.node_damping_Ns_per_m =
      def.node_damping_Ns_per_m.size() == 0 ? Eigen::VectorXd::Zero(static_cast<Eigen::Index>(n))
                                            : def.node_damping_Ns_per_m;
  m.inv_mass_free_per_kg.resize(static_cast<Eigen::Index>(n));
  for (std::size_t i = 0; i < n; ++i) {
    const auto e = static_cast<Eigen::Index>(i);
    if (!std::isfinite(m.mass_kg[e]) || m.mass_kg[e] <= 0.0)
      Fail("mass_kg[" + std::to_string(i) + "] = " + std::to_string(m.mass_kg[e]) +
           " must be finite and > 0");
    CheckCoefficient(m.node_damping_Ns_per_m[e], "node_damping_Ns_per_m", i);
    m.inv_mass_free_per_kg[e] = m.fixed[i] ? 0.0 : 1.0 / m.mass_kg[e];
  }
  m.gravity_m_per_s2 = def.gravity_m_per_s2;
}

// Springs, with their capacity reserved so cuts never reallocate.
void CopyMsmSprings(const MsmDef& def, std::size_t n, MsmModel& m) {
  const std::size_t s = def.springs.size();
  CheckSize(def.spring_rest_m.size(), s, "spring_rest_m", true);
  CheckSize(def.spring_k_N_per_m.size(), s, "spring_k_N_per_m", false);
  CheckSize(def.spring_c_Ns_per_m.size(), s, "spring_c_Ns_per_m", true);
  if (def.spring_capacity != 0 && static_cast<std::size_t>(def.spring_capacity) < s)
    Fail("spring_capacity " + std::to_string(def.spring_capacity) + " < number of springs " +
         std::to_string(s));
  m.spring_capacity = def.spring_capacity == 0 ? static_cast<std::int32_t>(s) : def.spring_capacity;
  const auto cap = static_cast<std::size_t>(m.spring_capacity);
  m.spring_i.reserve(cap);
  m.spring_j.reserve(cap);
  m.spring_rest_m.reserve(cap);
  m.spring_k_N_per_m.reserve(cap);
  m.spring_c_Ns_per_m.reserve(cap);
  for (std::size_t k = 0; k < s; ++k) {
    const auto [i, j] = def.springs[k];
    if (i < 0 || j < 0 || static_cast<std::size_t>(i) >= n || static_cast<std::size_t>(j) >= n)
      Fail("springs[" + std::to_string(k) + "] = (" + std::to_string(i) + ", " +
           std::to_string(j) + ") has a node index outside [0, " + std::to_string(n) + ")");
    if (i == j) Fail("springs[" + std::to_string(k) + "] joins node " + std::to_string(i) + " to itself");
    const double rest = def.spring_rest_m.empty() ? (def.x0_m.col(j) - def.x0_m.col(i)).norm()
                                                  : def.spring_rest_m[k];
    if (!std::isfinite(rest) || rest < 0.0)
      Fail("spring_rest_m[" + std::to_string(k) + "] must be finite and >= 0");
    CheckCoefficient(def.spring_k_N_per_m[k], "spring_k_N_per_m", k);
    const double c = def.spring_c_Ns_per_m.empty() ? 0.0 : def.spring_c_Ns_per_m[k];
    CheckCoefficient(c, "spring_c_Ns_per_m", k);
    m.spring_i.push_back(i);
    m.spring_j.push_back(j);
    m.spring_rest_m.push_back(rest);
    m.spring_k_N_per_m.push_back(def.spring_k_N_per_m[k]);
    m.spring_c_Ns_per_m.push_back(c);
  }
}

void CopyMsmAnchors(const MsmDef& def, std::size_t n, MsmModel& m) {
  const std::size_t a = def.anchor_node.size();
  CheckSize(static_cast<std::size_t>(def.anchor_point_W_m.cols()), a, "anchor_point_W_m", false);
  CheckSize(def.anchor_k_N_per_m.size(), a, "anchor_k_N_per_m", false);
  CheckSize(def.anchor_c_Ns_per_m.size(), a, "anchor_c_Ns_per_m", true);
  if (a > 0 && !def.anchor_point_W_m.allFinite()) Fail("anchor_point_W_m contains NaN/inf");
  for (std::size_t k = 0; k < a; ++k) {
    const std::int32_t i = def.anchor_node[k];
    if (i < 0 || static_cast<std::size_t>(i) >= n)
      Fail("anchor_node[" + std::to_string(k) + "] = " + std::to_string(i) + " is outside [0, " +
           std::to_string(n) + ")");
    CheckCoefficient(def.anchor_k_N_per_m[k], "anchor_k_N_per_m", k);
    if (!def.anchor_c_Ns_per_m.empty()) CheckCoefficient(def.anchor_c_Ns_per_m[k], "anchor_c_Ns_per_m", k);
  }
  m.anchor_node = def.anchor_node;
  m.anchor_point_W_m = a > 0 ? def.anchor_point_W_m : Eigen::Matrix3Xd(3, 0);
  m.anchor_k_N_per_m = def.anchor_k_N_per_m;
  m.anchor_c_Ns_per_m = def.anchor_c_Ns_per_m.empty() ? std::vector<double>(a, 0.0) : def.anchor_c_Ns_per_m;
}

// Node damping and every anchor summed per node, so the step folds them
// into one pass over the nodes.
void SumMsmAnchorsPerNode(std::size_t n, MsmModel& m) {
  m.absolute_damping_Ns_per_m = m.node_damping_Ns_per_m;
  m.anchor_k_sum_N_per_m = Eigen::VectorXd::Zero(static_cast<Eigen::Index>(n));
  m.anchor_kp_sum_N = Eigen::Matrix3Xd::Zero(3, static_cast<Eigen::Index>(n));
  for (std::size_t k = 0; k < m.anchor_node.size(); ++k) {
    const Eigen::Index i = m.anchor_node[k];
    m.absolute_damping_Ns_per_m[i] += m.anchor_c_Ns_per_m[k];
    m.anchor_k_sum_N_per_m[i] += m.anchor_k_N_per_m[k];
    m.anchor_kp_sum_N.col(i) += m.anchor_k_N_per_m[k] * m.anchor_point_W_m.col(static_cast<Eigen::Index>(k));
  }
}

// Each node's springs in build order (node_springs), for `capacity` nodes.
void BuildMsmAdjacency(const MsmDef& def, std::size_t capacity, MsmModel& m) {
  const std::size_t s = m.spring_i.size();
  std::vector<std::int32_t> degree(capacity, 0);
  for (std::size_t k = 0; k < s; ++k) {
    ++degree[static_cast<std::size_t>(m.spring_i[k])];
    ++degree[static_cast<std::size_t>(m.spring_j[k])];
  }
  const std::int32_t built_max = degree.empty() ? 0 : *std::max_element(degree.begin(), degree.end());
  if (def.max_node_degree < 0) Fail("max_node_degree must be >= 0");
  if (def.max_node_degree != 0 && def.max_node_degree < built_max)
    Fail("max_node_degree " + std::to_string(def.max_node_degree) + " < a node's degree at build (" +
         std::to_string(built_max) + ")");
  m.max_degree = def.max_node_degree == 0 ? built_max : def.max_node_degree;
  m.node_degree.assign(capacity, 0);
  m.node_springs.assign(capacity * static_cast<std::size_t>(m.max_degree), -1);
  for (std::size_t k = 0; k < s; ++k) {
    for (const std::int32_t end : {m.spring_i[k], m.spring_j[k]}) {
      const auto e = static_cast<std::size_t>(end);
      m.node_springs[e * static_cast<std::size_t>(m.max_degree) + static_cast<std::size_t>(m.node_degree[e]++)] =
          static_cast<std::int32_t>(k);
    }
  }
}

// Room for nodes added later (cutting): dormant nodes at the origin, fixed,
// unit placeholder mass, nothing attached.
void AddDormantMsmNodes(std::size_t n, std::size_t capacity, MsmModel& m) {
  m.num_nodes = static_cast<std::int32_t>(capacity);
  m.node_live.assign(capacity, 0);
  std::fill(m.node_live.begin(), m.node_live.begin() + static_cast<std::ptrdiff_t>(n), 1);
  if (capacity <= n) return;
  const auto node_cap = static_cast<Eigen::Index>(capacity), en = static_cast<Eigen::Index>(n);
  m.x0_m.conservativeResize(3, node_cap);
  m.x0_m.rightCols(node_cap - en).setZero();
  m.mass_kg.conservativeResize(node_cap);
  m.mass_kg.tail(node_cap - en).setOnes();
  m.inv_mass_free_per_kg.conservativeResize(node_cap);
  m.inv_mass_free_per_kg.tail(node_cap - en).setZero();
  m.fixed.resize(capacity, 1);
  m.node_damping_Ns_per_m.conservativeResize(node_cap);
  m.node_damping_Ns_per_m.tail(node_cap - en).setZero();
  m.absolute_damping_Ns_per_m.conservativeResize(node_cap);
  m.absolute_damping_Ns_per_m.tail(node_cap - en).setZero();
  m.anchor_k_sum_N_per_m.conservativeResize(node_cap);
  m.anchor_k_sum_N_per_m.tail(node_cap - en).setZero();
  m.anchor_kp_sum_N.conservativeResize(3, node_cap);
  m.anchor_kp_sum_N.rightCols(node_cap - en).setZero();
}

}  // namespace

MsmModel BuildMsmModel(const MsmDef& def) {
  MsmModel m;
  CopyMsmNodes(def, m);
  const auto n = static_cast<std::size_t>(def.x0_m.cols());
  CopyMsmSprings(def, n, m);
  CopyMsmAnchors(def, n, m);
  SumMsmAnchorsPerNode(n, m);
  if (def.node_capacity != 0 && static_cast<std::size_t>(def.node_capacity) < n)
    Fail("node_capacity " + std::to_string(def.node_capacity) + " < number of nodes " + std::to_string(n));
  const std::size_t capacity = def.node_capacity == 0 ? n : static_cast<std::size_t>(def.node_capacity);
  BuildMsmAdjacency(def, capacity, m);
  AddDormantMsmNodes(n, capacity, m);
  if (std::isnan(def.max_kinetic_energy_J) || def.max_kinetic_energy_J <= 0.0)
    Fail("max_kinetic_energy_J must be > 0 (use infinity to disable the check)");
  m.max_kinetic_energy_J = def.max_kinetic_energy_J;
  return m;
}

}  // namespace hapsim::core
