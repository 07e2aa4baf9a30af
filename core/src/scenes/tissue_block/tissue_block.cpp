#include "hapsim/core/scenes/tissue_block/tissue_block.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>
#include <stdexcept>

#include "hapsim/core/msm/stability.h"
#include "hapsim/core/scenes/scene_builders.h"

namespace hapsim::core {
namespace {

// Fraction of the critical step a scene may use: the Gershgorin bound is
// conservative near rest, but stretched springs stiffen transversally.
constexpr double kCriticalStepSafety = 0.9;

// MakeTissueGridDef's steps, in order.

// An n x n grid in the xy-plane centred on the origin, its border fixed.
void PlaceTissueGridNodes(const TissueBlockParams& p, double spacing_m, MsmDef& d) {
  const int n = p.grid_nodes;
  d.x0_m.resize(3, n * n);
  d.fixed.assign(static_cast<std::size_t>(n * n), 0);
  for (int r = 0; r < n; ++r) {
    for (int c = 0; c < n; ++c) {
      const int i = r * n + c;
      d.x0_m.col(i) << -0.5 * p.size_m + c * spacing_m, -0.5 * p.size_m + r * spacing_m, 0.0;
      d.fixed[static_cast<std::size_t>(i)] = (r == 0 || c == 0 || r == n - 1 || c == n - 1) ? 1 : 0;
    }
  }
  d.mass_kg = Eigen::VectorXd::Constant(n * n, p.node_mass_kg);
  d.node_damping_Ns_per_m = Eigen::VectorXd::Constant(n * n, p.damping_Ns_per_m);
}

// Structural springs between grid neighbours and shear springs across each
// cell, shortened by the prestretch.
void AddTissueGridSprings(const TissueBlockParams& p, double spacing_m, MsmDef& d) {
  const int n = p.grid_nodes;
  const double shrink = 1.0 / (1.0 + p.prestretch);
  auto add = [&](int i, int j, double k, double length_m) {
    d.springs.push_back({i, j});
    d.spring_rest_m.push_back(length_m * shrink);
    d.spring_k_N_per_m.push_back(k);
    d.spring_c_Ns_per_m.push_back(p.spring_damping_Ns_per_m);
  };
  // Spring order: row by row, and within a row in groups whose springs share
  // no node (even/odd horizontals, verticals, both diagonals). Consecutive
  // springs then never update the same node's force, so the scatter has no
  // store-to-load chains, while each group stays within two grid rows
  // (cache-local).
  const double diagonal_m = spacing_m * std::sqrt(2.0);
  for (int r = 0; r < n; ++r) {
    for (int parity = 0; parity < 2; ++parity)
      for (int c = parity; c + 1 < n; c += 2) add(r * n + c, r * n + c + 1, p.spring_stiffness_N_per_m, spacing_m);
    if (r + 1 == n) break;
    for (int c = 0; c < n; ++c) add(r * n + c, (r + 1) * n + c, p.spring_stiffness_N_per_m, spacing_m);
    for (int c = 0; c + 1 < n; ++c) add(r * n + c, (r + 1) * n + c + 1, p.shear_stiffness_N_per_m, diagonal_m);
    for (int c = 0; c + 1 < n; ++c) add(r * n + c + 1, (r + 1) * n + c, p.shear_stiffness_N_per_m, diagonal_m);
  }
}

// Every free node anchored to its rest position (the tissue underneath).
void AnchorTissueGridNodes(const TissueBlockParams& p, MsmDef& d) {
  for (int i = 0; i < p.grid_nodes * p.grid_nodes; ++i) {
    if (d.fixed[static_cast<std::size_t>(i)]) continue;
    d.anchor_node.push_back(i);
    d.anchor_k_N_per_m.push_back(p.anchor_stiffness_N_per_m);
  }
  d.anchor_point_W_m.resize(3, static_cast<Eigen::Index>(d.anchor_node.size()));
  for (std::size_t a = 0; a < d.anchor_node.size(); ++a)
    d.anchor_point_W_m.col(static_cast<Eigen::Index>(a)) = d.x0_m.col(d.anchor_node[a]);
}

}  // namespace

MsmDef MakeTissueGridDef(const TissueBlockParams& p) {
  const double spacing_m = p.size_m / (p.grid_nodes - 1);
  MsmDef d;
  PlaceTissueGridNodes(p, spacing_m, d);
  AddTissueGridSprings(p, spacing_m, d);
  AnchorTissueGridNodes(p, d);
  d.max_kinetic_energy_J = p.max_kinetic_energy_J;
  return d;
}

TissueBlockScene::TissueBlockScene(const TissueBlockParams& params)
    : params_(params), spacing_m_(params.size_m / (params.grid_nodes - 1)) {
  model_ = BuildMsmModel(MakeTissueGridDef(params_));
  state_ = MakeMsmState(model_);
  initial_state_ = state_;
  workspace_ = MakeMsmWorkspace(model_);
  workspace_.cg_max_iterations = TissueBlockLimits::kMaxCgIterations;  // bounded tick cost
  region_ = MakeLocalRegion(model_);
  rest_speed_m_per_s_ =
      params_.rest_displacement_m * std::sqrt(params_.anchor_stiffness_N_per_m / params_.node_mass_kg);

  // A contact node carries at most the full penalty spring-damper.
  critical_dt_s_ = core::CriticalTimeStep_s(EstimateModeBounds(model_, params_.contact_stiffness_N_per_m,
                                                               params_.contact_damping_Ns_per_m),
                                            params_.integrator);
  if (!(params_.dt_s <= kCriticalStepSafety * critical_dt_s_)) {
    std::ostringstream msg;
    msg << "tissue_block: parameter 'dt_s' = " << params_.dt_s << " s is unstable for integrator "
        << ToString(params_.integrator.kind) << ": the critical step estimate is " << critical_dt_s_
        << " s (use dt_s <= " << kCriticalStepSafety * critical_dt_s_
        << ", a heavier node_mass_kg, lower stiffnesses, more damping, or integrator 5 = backward_euler)";
    throw std::invalid_argument(msg.str());
  }

  // One vertex slot per node (slot i = node i), two triangles per cell.
  const int n = params_.grid_nodes;
  topology_ = MeshTopology({.vertex_capacity = static_cast<std::uint32_t>(n * n),
                            .triangle_capacity = static_cast<std::uint32_t>(2 * (n - 1) * (n - 1)),
                            .part_names = {"tissue"},
                            .log_capacity = 0});  // never edited
  for (int i = 0; i < n * n; ++i) topology_.AddVertex();
  for (int r = 0; r + 1 < n; ++r) {
    for (int c = 0; c + 1 < n; ++c) {
      const auto a = static_cast<std::uint32_t>(r * n + c), b = a + 1,
                 d = a + static_cast<std::uint32_t>(n), e = d + 1;
      topology_.AddTriangle(a, b, e, 0);  // counter-clockwise seen from +z
      topology_.AddTriangle(a, e, d, 0);
    }
  }
  topology_.Seal();
  outputs_.status.layer_names = {"tissue"};
}

TissueBlockScene::Contact TissueBlockScene::FindContact(const ToolInput& tool) const {
  Contact c;
  const Eigen::Vector3d& tip = tool.tip_W_m;
  if (!tool.valid || !tip.allFinite()) return c;
  // Cell from the rest grid (lateral node motion under a press is small).
  const int n = params_.grid_nodes;
  const double u = (tip.x() + 0.5 * params_.size_m) / spacing_m_;
  const double w = (tip.y() + 0.5 * params_.size_m) / spacing_m_;
  if (!(u >= 0.0 && u <= n - 1 && w >= 0.0 && w <= n - 1)) return c;  // also rejects huge values
  const int col = std::min(static_cast<int>(u), n - 2), row = std::min(static_cast<int>(w), n - 2);
  const double fu = u - col, fw = w - row;
  c.nodes = {NodeIndex(row, col), NodeIndex(row, col + 1), NodeIndex(row + 1, col),
             NodeIndex(row + 1, col + 1)};
  c.weights = {(1 - fu) * (1 - fw), fu * (1 - fw), (1 - fu) * fw, fu * fw};
  double surface_z_m = 0.0, surface_vz_m_per_s = 0.0;
  for (std::size_t k = 0; k < 4; ++k) {
    surface_z_m += c.weights[k] * state_.x_m(2, c.nodes[k]);
    surface_vz_m_per_s += c.weights[k] * state_.v_m_per_s(2, c.nodes[k]);
  }
  const double penetration_m = surface_z_m - tip.z();
  if (!(penetration_m > 0.0)) return c;
  c.active = true;
  c.penetration_m = std::min(penetration_m, params_.max_penetration_m);
  // A hand moves well below 10 m/s; anything else is a bad device reading.
  const double reported_vz = tool.velocity_W_m_per_s.z();
  const double tip_vz_m_per_s = std::isfinite(reported_vz) ? std::clamp(reported_vz, -kMaxToolSpeed_m_per_s, kMaxToolSpeed_m_per_s) : 0.0;
  // Clamped at 0: the damper never pulls the tool into the tissue.
  c.push_N = std::max(0.0, params_.contact_stiffness_N_per_m * c.penetration_m +
                               params_.contact_damping_Ns_per_m * (surface_vz_m_per_s - tip_vz_m_per_s));
  return c;
}

void TissueBlockScene::ApplyContactForce(const Contact& c) {
  for (const std::int32_t i : loaded_nodes_) state_.f_ext_N.col(i).setZero();
  if (!c.active) return;
  for (std::size_t k = 0; k < 4; ++k) state_.f_ext_N(2, c.nodes[k]) -= c.weights[k] * c.push_N;
  loaded_nodes_ = c.nodes;
}

double TissueBlockScene::LocalSurfaceStiffness_N_per_m(const Contact& c) const {
  // z-stiffness of each corner node (anchor + tangent stiffness of its
  // springs projected on z), combined as independent springs loaded through
  // the bilinear weights: compliance = sum w_a^2 / k_a. Ignores the coupling
  // between the corners, so it overestimates the true surface stiffness.
  double compliance_m_per_N = 0.0;
  for (std::size_t k = 0; k < 4; ++k) {
    const std::int32_t i = c.nodes[k];
    double kz = model_.fixed[static_cast<std::size_t>(i)] ? std::numeric_limits<double>::infinity()
                                                          : params_.anchor_stiffness_N_per_m;
    const std::int32_t* springs = model_.SpringsOf(i);
    for (std::int32_t e = 0; e < model_.DegreeOf(i) && std::isfinite(kz); ++e) {
      const auto us = static_cast<std::size_t>(springs[e]);
      const Eigen::Vector3d d = state_.x_m.col(model_.spring_j[us]) - state_.x_m.col(model_.spring_i[us]);
      const double l = d.norm();
      const double uz = d.z() / l;
      const double geo = std::max(0.0, 1.0 - model_.spring_rest_m[us] / l);
      kz += model_.spring_k_N_per_m[us] * (uz * uz + geo * (1.0 - uz * uz));
    }
    compliance_m_per_N += c.weights[k] * c.weights[k] / kz;
  }
  return compliance_m_per_N > 0.0 ? 1.0 / compliance_m_per_N : std::numeric_limits<double>::infinity();
}

void TissueBlockScene::UpdateOutputs(const ToolInput& tool, const Contact& c) {
  const Eigen::Vector3d n_W = Eigen::Vector3d::UnitZ();
  const double force_N = c.push_N;
  // damping_Ns_per_m stays 0: force_N already contains the contact damper at
  // this tick, and the bridge adds its own coupling damping.
  outputs_.tool_force_W_N = force_N * n_W;
  outputs_.force_model = LocalForceModel{};
  if (c.active) {
    // Tip and tissue are springs in series: k = (1/k_c + 1/k_surface)^-1.
    const double k_eff = 1.0 / (1.0 / params_.contact_stiffness_N_per_m +
                                1.0 / LocalSurfaceStiffness_N_per_m(c));
    outputs_.force_model.state = ContactState::kContact;
    outputs_.force_model.normal_W = n_W;
    outputs_.force_model.stiffness_N_per_m = k_eff;
    // Anchor such that k (anchor - tip)·n = F at the current tip.
    outputs_.force_model.anchor_W_m = tool.tip_W_m + (force_N / k_eff) * n_W;
  }
  const bool tip_ok = tool.valid && tool.tip_W_m.allFinite();
  outputs_.status.tip_depth_m = tip_ok ? std::max(0.0, -tool.tip_W_m.z()) : 0.0;
  outputs_.status.current_layer = c.active ? 0 : -1;
  if (c.active != was_in_contact_) {
    outputs_.events.Push({state_.t_s, c.active ? SceneEventKind::kContactBegin : SceneEventKind::kContactEnd, 0,
                          tip_ok ? tool.tip_W_m : Eigen::Vector3d::Zero()});
    was_in_contact_ = c.active;
  }
}

void TissueBlockScene::PutAtRest() {
  const double t_s = state_.t_s;
  const std::uint64_t blowups = state_.blowups;
  state_ = initial_state_;  // same sizes: copies, no allocation
  state_.t_s = t_s;
  state_.blowups = blowups;
}

void TissueBlockScene::RecoverFromBlowup() {
  PutAtRest();
  loaded_nodes_ = {};
  region_seed_ = -1;
  LogNumericalReset(state_.t_s);
}

void TissueBlockScene::Step(const ToolInput& tool, double dt_s) {
  if (!(std::isfinite(dt_s) && dt_s > 0.0)) return;
  const int substeps = static_cast<int>(std::min<double>(TissueBlockLimits::kMaxSubsteps, std::ceil(dt_s / params_.dt_s)));
  const double h = std::min(dt_s / substeps, params_.dt_s);
  if (asleep_) {
    const Contact c = FindContact(tool);
    if (!c.active) {
      for (int k = 0; k < substeps; ++k) state_.t_s += h;  // the clock as the full step runs it
      UpdateOutputs(tool, c);
      return;
    }
    asleep_ = false;  // touched: step on from the rest state
  }
  bool touched = false;
  for (int k = 0; k < substeps; ++k) {
    const Contact c = FindContact(tool);
    touched = touched || c.active;
    ApplyContactForce(c);
    if (!Advance(c, h).ok) {
      RecoverFromBlowup();
      break;
    }
  }
  const Contact c = FindContact(tool);
  if (!touched && !c.active) SleepIfAtRest();
  UpdateOutputs(tool, c);
}

// Out of contact (no external force) the block rings down towards its rest
// state, the initial one. Within rest_displacement_m of it in every
// coordinate, and with no node faster than rest_speed_m_per_s_ (the speed of
// a node ringing at that amplitude on its anchor alone), it is put exactly at
// rest: what is dropped is a ring-down below that amplitude.
void TissueBlockScene::SleepIfAtRest() {
  if (params_.rest_displacement_m <= 0.0) return;
  if ((state_.x_m - initial_state_.x_m).cwiseAbs().maxCoeff() > params_.rest_displacement_m) return;
  if (state_.v_m_per_s.cwiseAbs().maxCoeff() > rest_speed_m_per_s_) return;
  PutAtRest();
  asleep_ = true;
}

StepReport TissueBlockScene::Advance(const Contact& c, double h_s) {
  if (params_.local_update_hops == 0 || !c.active) {
    return StepMsm(model_, state_, h_s, params_.integrator, workspace_);
  }
  // Centre the region on the corner carrying most of the load; reselect
  // only when that changes (selection is allocation-free but O(region)).
  const auto heaviest = static_cast<std::size_t>(
      std::max_element(c.weights.begin(), c.weights.end()) - c.weights.begin());
  if (c.nodes[heaviest] != region_seed_) {
    region_seed_ = c.nodes[heaviest];
    SelectLocalRegion(model_, region_seed_, params_.local_update_hops, region_);
  }
  return StepMsmLocal(model_, state_, h_s, params_.integrator, workspace_, region_);
}

void TissueBlockScene::Reset() {
  state_ = initial_state_;
  loaded_nodes_ = {};
  region_seed_ = -1;
  was_in_contact_ = false;
  asleep_ = false;
  FinishReset();
}

std::uint64_t TissueBlockScene::StateHash() const {
  StateHasher h;
  AddCommonSceneState(h, *this, outputs_.reset_epoch);
  // Vertices_m() is state_.x_m; the workspace and the region are scratch and
  // a cache (the integrators start from zero, the region is a function of the
  // tool's cell).
  h.Add(state_.x_m).Add(state_.v_m_per_s).Add(state_.f_ext_N).Add(state_.f_residual_N).Add(state_.blowups);
  h.Add(loaded_nodes_).Add(was_in_contact_).Add(asleep_);
  return h.Value();
}

std::unique_ptr<Scene> MakeTissueBlockScene(const std::map<std::string, double>& params) {
  return std::make_unique<TissueBlockScene>(ParseTissueBlockParams(params));
}

}  // namespace hapsim::core
