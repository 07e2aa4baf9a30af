#include "hapsim/core/msm/msm_topology.h"

#include <cmath>

#include "hapsim/core/assert.h"

namespace hapsim::core {

namespace {

std::int32_t* Adjacency(MsmModel& m, std::int32_t node) {
  return m.node_springs.data() + static_cast<std::size_t>(node) * static_cast<std::size_t>(m.max_degree);
}

// Replaces spring `from` by `to` in node's list; `to` == kNoSpring removes
// it (the last entry moves into its place).
void ReplaceInAdjacency(MsmModel& m, std::int32_t node, std::int32_t from, std::int32_t to) {
  std::int32_t* list = Adjacency(m, node);
  std::int32_t& degree = m.node_degree[static_cast<std::size_t>(node)];
  for (std::int32_t k = 0; k < degree; ++k) {
    if (list[k] != from) continue;
    if (to == kNoSpring) {
      list[k] = list[degree - 1];
      list[--degree] = kNoSpring;
    } else {
      list[k] = to;
    }
    return;
  }
  HAPSIM_DEMAND(false, "MSM adjacency out of step with the springs");
}

bool IsLive(const MsmModel& m, std::int32_t node) {
  return node >= 0 && node < m.num_nodes && m.node_live[static_cast<std::size_t>(node)] != 0;
}

}  // namespace

std::int32_t FindSpring(const MsmModel& m, std::int32_t a, std::int32_t b) {
  if (a < 0 || a >= m.num_nodes) return kNoSpring;
  const std::int32_t* list = m.SpringsOf(a);
  for (std::int32_t k = 0; k < m.DegreeOf(a); ++k) {
    const auto s = static_cast<std::size_t>(list[k]);
    if (m.spring_i[s] == b || m.spring_j[s] == b) return list[k];
  }
  return kNoSpring;
}

void RemoveSpring(MsmModel& m, std::int32_t s) {
  HAPSIM_DEMAND(s >= 0 && s < m.NumSprings(), "RemoveSpring: no such spring");
  const std::int32_t last = m.NumSprings() - 1;
  const auto k = static_cast<std::size_t>(s), l = static_cast<std::size_t>(last);
  ReplaceInAdjacency(m, m.spring_i[k], s, kNoSpring);
  ReplaceInAdjacency(m, m.spring_j[k], s, kNoSpring);
  if (s != last) {  // the last spring moves into slot s
    ReplaceInAdjacency(m, m.spring_i[l], last, s);
    ReplaceInAdjacency(m, m.spring_j[l], last, s);
    m.spring_i[k] = m.spring_i[l];
    m.spring_j[k] = m.spring_j[l];
    m.spring_rest_m[k] = m.spring_rest_m[l];
    m.spring_k_N_per_m[k] = m.spring_k_N_per_m[l];
    m.spring_c_Ns_per_m[k] = m.spring_c_Ns_per_m[l];
  }
  m.spring_i.pop_back();
  m.spring_j.pop_back();
  m.spring_rest_m.pop_back();
  m.spring_k_N_per_m.pop_back();
  m.spring_c_Ns_per_m.pop_back();
}

std::int32_t AddSpring(MsmModel& m, std::int32_t i, std::int32_t j, double rest_m, double k_N_per_m,
                       double c_Ns_per_m) {
  HAPSIM_DEMAND(IsLive(m, i) && IsLive(m, j) && i != j, "AddSpring: nodes must be live and distinct");
  HAPSIM_DEMAND(std::isfinite(rest_m) && rest_m >= 0 && std::isfinite(k_N_per_m) && k_N_per_m >= 0 &&
                    std::isfinite(c_Ns_per_m) && c_Ns_per_m >= 0,
                "AddSpring: rest length, stiffness and damping must be finite and >= 0");
  if (m.NumSprings() >= m.spring_capacity || m.DegreeOf(i) >= m.max_degree || m.DegreeOf(j) >= m.max_degree) {
    return kNoSpring;
  }
  const std::int32_t s = m.NumSprings();
  m.spring_i.push_back(i);  // within reserved capacity: no reallocation
  m.spring_j.push_back(j);
  m.spring_rest_m.push_back(rest_m);
  m.spring_k_N_per_m.push_back(k_N_per_m);
  m.spring_c_Ns_per_m.push_back(c_Ns_per_m);
  Adjacency(m, i)[m.node_degree[static_cast<std::size_t>(i)]++] = s;
  Adjacency(m, j)[m.node_degree[static_cast<std::size_t>(j)]++] = s;
  return s;
}

void ActivateNode(MsmModel& m, MsmState& state, std::int32_t node, const NodeDef& def) {
  HAPSIM_DEMAND(node >= 0 && node < m.num_nodes && !m.node_live[static_cast<std::size_t>(node)],
                "ActivateNode: the node is not a dormant node of the model");
  HAPSIM_DEMAND(def.x_W_m.allFinite() && std::isfinite(def.mass_kg) && def.mass_kg > 0.0 &&
                    std::isfinite(def.damping_Ns_per_m) && def.damping_Ns_per_m >= 0.0 &&
                    std::isfinite(def.anchor_k_N_per_m) && def.anchor_k_N_per_m >= 0.0 &&
                    std::isfinite(def.anchor_c_Ns_per_m) && def.anchor_c_Ns_per_m >= 0.0,
                "ActivateNode: position, mass, damping and anchor must be finite (mass > 0, the rest >= 0)");
  const auto i = static_cast<Eigen::Index>(node);
  m.node_live[static_cast<std::size_t>(node)] = 1;
  m.fixed[static_cast<std::size_t>(node)] = 0;
  m.x0_m.col(i) = def.x_W_m;
  m.mass_kg[i] = def.mass_kg;
  m.inv_mass_free_per_kg[i] = 1.0 / def.mass_kg;
  m.node_damping_Ns_per_m[i] = def.damping_Ns_per_m;
  m.absolute_damping_Ns_per_m[i] = def.damping_Ns_per_m + def.anchor_c_Ns_per_m;
  m.anchor_k_sum_N_per_m[i] = def.anchor_k_N_per_m;
  m.anchor_kp_sum_N.col(i) = def.anchor_k_N_per_m * def.x_W_m;
  state.x_m.col(i) = def.x_W_m;
  state.v_m_per_s.col(i).setZero();
  state.f_ext_N.col(i).setZero();
  state.f_residual_N.col(i).setZero();
}

void DeactivateNode(MsmModel& m, MsmState& state, std::int32_t node) {
  HAPSIM_DEMAND(IsLive(m, node), "DeactivateNode: the node is not live");
  while (m.DegreeOf(node) > 0) RemoveSpring(m, m.SpringsOf(node)[0]);
  const auto i = static_cast<Eigen::Index>(node);
  m.node_live[static_cast<std::size_t>(node)] = 0;
  m.fixed[static_cast<std::size_t>(node)] = 1;
  m.inv_mass_free_per_kg[i] = 0.0;
  m.node_damping_Ns_per_m[i] = 0.0;
  m.absolute_damping_Ns_per_m[i] = 0.0;
  m.anchor_k_sum_N_per_m[i] = 0.0;
  m.anchor_kp_sum_N.col(i).setZero();
  state.v_m_per_s.col(i).setZero();
  state.f_ext_N.col(i).setZero();
  state.f_residual_N.col(i).setZero();
}

void SetResidualForce(MsmState& state, std::int32_t node, const Eigen::Vector3d& f_N) {
  HAPSIM_DEMAND(node >= 0 && node < state.f_residual_N.cols(), "SetResidualForce: no such node");
  state.f_residual_N.col(node) = f_N;
}

}  // namespace hapsim::core
