#include "hapsim/core/needle/force_net.h"

#include <cmath>
#include <stdexcept>
#include <string>

#include <Eigen/Geometry>

#include "hapsim/core/msm/msm_step.h"
#include "hapsim/core/msm/msm_forces.h"
#include "hapsim/core/msm/msm_model.h"
#include "hapsim/core/msm/msm_state.h"

namespace hapsim::core {

namespace {

void Require(bool ok, const std::string& what) {
  if (!ok) throw std::invalid_argument("force net: " + what);
}

// Static influence vector from the MSM core: N1 fixed and displaced by
// unit_m along z, everything else relaxed to equilibrium by backward Euler
// with a step so long that inertia is negligible (each step is then a Newton
// step on the statics; the system is linear, so a few steps reach round-off).
Eigen::VectorXd SolveInfluence(const HexNetTopology& topo, double K, double ks, double& residual_N) {
  const std::int32_t n = topo.NumNodes();
  MsmDef def;
  def.x0_m = Eigen::Matrix3Xd::Zero(3, n);
  def.x0_m.topRows<2>() = topo.offset_T_m;
  def.mass_kg = Eigen::VectorXd::Constant(n, 1e-3);  // irrelevant for statics
  def.fixed.assign(static_cast<std::size_t>(n), 0);
  def.fixed[0] = 1;  // N1 is carried by the needle
  for (const auto& s : topo.springs) {
    def.springs.push_back(s);
    def.spring_rest_m.push_back(0.0);  // tensioned membrane (see header)
    def.spring_k_N_per_m.push_back(ks);
  }
  for (std::int32_t i = 0; i < n; ++i) {
    def.anchor_node.push_back(i);
    def.anchor_k_N_per_m.push_back(K);
  }
  def.anchor_point_W_m = def.x0_m;
  const MsmModel model = BuildMsmModel(def);
  MsmState state = MakeMsmState(model);
  // Edge traction: the skin outside the net holds the tensioned rim, so the
  // rest lattice is an equilibrium.
  Eigen::Matrix3Xd f;
  ComputeForces(model, state, state.x_m, state.v_m_per_s, f);
  state.f_ext_N = -f;

  constexpr double kUnit_m = 1e-3;
  state.x_m(2, 0) = -kUnit_m;
  MsmWorkspace ws = MakeMsmWorkspace(model);
  ws.cg_relative_tolerance = 1e-14;
  ws.cg_max_iterations = 10 * n;
  IntegratorChoice be;
  be.kind = IntegratorKind::kBackwardEuler;
  for (int it = 0; it < 4; ++it) {
    state.v_m_per_s.setZero();  // quasi-static: start every step at rest
    const StepReport r = StepMsm(model, state, 1e3, be, ws);
    if (!r.ok) throw std::runtime_error("force net: MSM static solve blew up");
  }
  state.v_m_per_s.setZero();
  ComputeForces(model, state, state.x_m, state.v_m_per_s, f);
  residual_N = f.rightCols(n - 1).cwiseAbs().maxCoeff();
  Eigen::VectorXd g = (def.x0_m.row(2) - state.x_m.row(2)).transpose() / kUnit_m;
  g[0] = 1.0;
  return g;
}

}  // namespace

ForceNetDef ForceNetDefFor(const TissueLayer& layer) {
  ForceNetDef d;
  d.rings_w = layer.rings_w;
  d.spacing_L_m = layer.spacing_L_m;
  d.virtual_K_N_per_m = layer.virtual_K_N_per_m;
  return d;
}

ForceNetModel BuildForceNet(const ForceNetDef& def) {
  Require(def.rings_w >= 2 && def.rings_w <= 40, "rings w must be in [2, 40]");
  Require(def.spacing_L_m > 0.0 && def.spacing_L_m < 0.05, "spring length L must be in (0, 0.05) m");
  Require(def.virtual_K_N_per_m > 0.0 && std::isfinite(def.virtual_K_N_per_m), "virtual spring K must be > 0");
  Require(def.tension_ratio > 0.0 && def.tension_ratio <= 1e4, "tension_ratio must be in (0, 1e4]");
  Require(def.threshold_ratio > 0.0 && def.threshold_ratio < 1.0, "threshold_ratio must be in (0, 1)");
  ForceNetModel m;
  m.def = def;
  m.topology = MakeHexNetTopology(def.rings_w, def.spacing_L_m);
  m.surface_k_N_per_m = def.tension_ratio * def.virtual_K_N_per_m;
  m.threshold_m = def.threshold_ratio * def.spacing_L_m;
  m.influence = SolveInfluence(m.topology, def.virtual_K_N_per_m, m.surface_k_N_per_m, m.static_residual_N);
  m.ring_influence.resize(def.rings_w);
  for (int j = 0; j < def.rings_w; ++j) {
    const auto b = m.topology.ring_first_node[static_cast<std::size_t>(j)];
    const auto e = m.topology.ring_first_node[static_cast<std::size_t>(j + 1)];
    m.ring_influence[j] = m.influence.segment(b, e - b).mean();
  }
  m.influence_sum = m.influence.sum();
  const double g_w = m.ring_influence[def.rings_w - 1];
  Require(g_w > 1e-12, "tension_ratio too small: the deformation never reaches ring w (g_w = " +
                           std::to_string(g_w) + ")");
  m.critical_deflection_m = m.threshold_m / g_w;
  return m;
}

ForceNetState MakeForceNetState(const ForceNetModel& model) {
  ForceNetState s;
  const auto n = model.topology.NumNodes();
  s.rest_W_m = Eigen::Matrix3Xd::Zero(3, n);
  s.x_W_m = Eigen::Matrix3Xd::Zero(3, n);
  s.ring_Z_m = Eigen::VectorXd::Zero(model.def.rings_w);
  return s;
}

void PlaceForceNet(const ForceNetModel& model, const Eigen::Vector3d& n1_W_m, const Eigen::Vector3d& normal_W,
                   ForceNetState& s) {
  s.n1_rest_W_m = n1_W_m;
  s.normal_W = normal_W;
  const Eigen::Vector3d t1 = normal_W.unitOrthogonal();
  const Eigen::Vector3d t2 = normal_W.cross(t1);
  const auto& off = model.topology.offset_T_m;
  for (Eigen::Index i = 0; i < off.cols(); ++i) s.rest_W_m.col(i) = n1_W_m + off(0, i) * t1 + off(1, i) * t2;
  s.x_W_m = s.rest_W_m;
  s.ring_Z_m.setZero();
  s.anchored = true;
}

void SolveForceNet(const ForceNetModel& model, const Eigen::Vector3d& n1_now_W_m, ForceNetState& s) {
  const Eigen::Vector3d u1 = n1_now_W_m - s.n1_rest_W_m;
  for (Eigen::Index i = 0; i < s.x_W_m.cols(); ++i) s.x_W_m.col(i) = s.rest_W_m.col(i) + model.influence[i] * u1;
  UpdateRingDeflections(model, s);
}

void UpdateRingDeflections(const ForceNetModel& model, ForceNetState& s) {
  const auto& first = model.topology.ring_first_node;
  for (int j = 0; j < model.def.rings_w; ++j) {
    const auto b = first[static_cast<std::size_t>(j)], e = first[static_cast<std::size_t>(j + 1)];
    double sum = 0.0;
    for (auto i = b; i < e; ++i) sum += (s.rest_W_m.col(i) - s.x_W_m.col(i)).dot(s.normal_W);
    s.ring_Z_m[j] = sum / (e - b);
  }
}

Eigen::Vector3d NetReactionOnTip_W_N(const ForceNetModel& model, const ForceNetState& s) {
  Eigen::Vector3d sum = Eigen::Vector3d::Zero();
  if (!s.anchored) return sum;
  for (Eigen::Index i = 0; i < s.x_W_m.cols(); ++i) sum += s.x_W_m.col(i) - s.rest_W_m.col(i);
  return -model.def.virtual_K_N_per_m * sum;
}

double PaperSurfaceForce_N(const ForceNetModel& model, const Eigen::VectorXd& ring_Z_m) {
  double f = ring_Z_m[0];
  for (int j = 2; j <= model.def.rings_w; ++j) f += 6.0 * (j - 1) * ring_Z_m[j - 1];
  return model.def.virtual_K_N_per_m * f;
}

}  // namespace hapsim::core
