#include "hapsim/core/needle/force_net.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>
#include <utility>

#include "hapsim/core/msm/msm_forces.h"
#include "hapsim/core/msm/msm_model.h"
#include "hapsim/core/msm/msm_state.h"
#include "hapsim/core/msm/msm_step.h"

namespace hapsim::core {

namespace {

void RequireForceNet(bool ok, const std::string& what) {
  if (!ok) throw std::invalid_argument("force net: " + what);
}

// The net as an MSM model in its own frame (t1, t2, n = x, y, z): N1 fixed
// (the needle carries it), pre-stretched surface springs, a zero-length
// virtual spring K per particle, and the rim traction that makes the rest
// lattice an equilibrium (held in state.f_ext_N).
struct NetSolver {
  MsmModel model;
  MsmState state;
  MsmWorkspace workspace;
  Eigen::Matrix3Xd forces;

  NetSolver(const HexNetTopology& topo, double K, double ks, double rest_m) {
    const std::int32_t n = topo.NumNodes();
    MsmDef def;
    def.x0_m = Eigen::Matrix3Xd::Zero(3, n);
    def.x0_m.topRows<2>() = topo.offset_T_m;
    def.mass_kg = Eigen::VectorXd::Constant(n, 1e-3);  // irrelevant for statics
    def.fixed.assign(static_cast<std::size_t>(n), 0);
    def.fixed[0] = 1;
    for (const auto& s : topo.springs) {
      def.springs.push_back(s);
      def.spring_rest_m.push_back(rest_m);
      def.spring_k_N_per_m.push_back(ks);
    }
    for (std::int32_t i = 0; i < n; ++i) {
      def.anchor_node.push_back(i);
      def.anchor_k_N_per_m.push_back(K);
    }
    def.anchor_point_W_m = def.x0_m;
    model = BuildMsmModel(def);
    state = MakeMsmState(model);
    ComputeForces(model, state, state.x_m, state.v_m_per_s, forces);
    state.f_ext_N = -forces;
    workspace = MakeMsmWorkspace(model);
    workspace.cg_relative_tolerance = 1e-14;
    workspace.cg_max_iterations = 10 * n;
  }

  // Backward-Euler steps with a 1000 s step from rest velocity until the
  // largest force on a free particle is below tol_N. Returns that force.
  double Relax(double tol_N, int max_steps, int* steps) {
    IntegratorChoice be;
    be.kind = IntegratorKind::kBackwardEuler;
    double residual = Residual();
    for (int it = 0; it < max_steps && residual > tol_N; ++it) {
      state.v_m_per_s.setZero();  // quasi-static: start every step at rest
      const StepReport r = StepMsm(model, state, 1e3, be, workspace);
      // The net is built from the scene's parameters: a solve that fails is
      // a parameter set the model cannot take (the client's INVALID_ARGUMENT).
      if (!r.ok) throw std::invalid_argument("force net: the static solve diverged for these net parameters");
      ++*steps;
      residual = Residual();
    }
    state.v_m_per_s.setZero();
    return residual;
  }

  double Residual() {
    ComputeForces(model, state, state.x_m, state.v_m_per_s, forces);
    return forces.rightCols(forces.cols() - 1).cwiseAbs().maxCoeff();
  }
};

// Converged when no free particle feels more than this [N].
constexpr double kStaticTolerance_N = 1e-9;
constexpr int kMaxNewtonSteps = 60;

// BuildForceNet's steps, in order.

void CheckForceNetDef(const ForceNetDef& def) {
  RequireForceNet(def.rings_w >= 2 && def.rings_w <= 40, "rings w must be in [2, 40]");
  RequireForceNet(def.spacing_L_m > 0.0 && def.spacing_L_m < 0.05, "spring length L must be in (0, 0.05) m");
  RequireForceNet(def.virtual_K_N_per_m > 0.0 && std::isfinite(def.virtual_K_N_per_m), "virtual spring K must be > 0");
  RequireForceNet(def.surface_ratio > 0.0 && def.surface_ratio <= 1e3, "surface_ratio must be in (0, 1e3]");
  RequireForceNet(def.prestretch >= 0.0 && def.prestretch <= 1.0, "prestretch must be in [0, 1]");
  RequireForceNet(def.puncture_force_N > 0.0 && std::isfinite(def.puncture_force_N), "puncture force must be > 0");
  RequireForceNet(def.table_step_m > 0.0 && def.table_max_depth_m >= 2.0 * def.table_step_m &&
                      def.table_max_depth_m / def.table_step_m <= 4000.0,
                  "table step and depth: 2 to 4000 steps");
}

// Lateral influence: N1 moved a micrometre along t1 from rest.
void MeasureForceNetLateralInfluence(ForceNetModel& m) {
  const double K = m.def.virtual_K_N_per_m;
  NetSolver net(m.topology, K, m.surface_k_N_per_m, m.surface_rest_m);
  constexpr double kLateral_m = 1e-6;
  net.state.x_m(0, 0) += kLateral_m;
  m.static_residual_N = net.Relax(kStaticTolerance_N * 1e-3, kMaxNewtonSteps, &m.newton_steps);
  m.lateral_influence = (net.state.x_m.row(0) - net.model.x0_m.row(0)).transpose() / kLateral_m;
  m.lateral_influence[0] = 1.0;
  m.lateral_stiffness_N_per_m = K * m.lateral_influence.sum();
}

// The depth table, each depth warm-started from the last, until the
// puncture force is passed by a fifth (the tip never goes deeper).
void TabulateForceNetDepths(ForceNetModel& m) {
  const ForceNetDef& def = m.def;
  const double K = def.virtual_K_N_per_m;
  NetSolver net(m.topology, K, m.surface_k_N_per_m, m.surface_rest_m);
  for (int k = 0;; ++k) {
    const double depth_m = k * def.table_step_m;
    net.state.x_m(2, 0) = -depth_m;
    m.static_residual_N = std::max(m.static_residual_N, net.Relax(kStaticTolerance_N, kMaxNewtonSteps, &m.newton_steps));
    m.displacement_T_m.push_back(net.state.x_m - net.model.x0_m);
    m.force_N.push_back(-K * m.displacement_T_m.back().row(2).sum());
    if (k >= 2 && m.force_N.back() >= 1.2 * def.puncture_force_N) break;
    RequireForceNet(depth_m + def.table_step_m <= def.table_max_depth_m + 1e-12,
                    "the puncture force " + std::to_string(def.puncture_force_N) + " N is not reached within " +
                        std::to_string(def.table_max_depth_m) + " m of indentation (at most " +
                        std::to_string(m.force_N.back()) + " N)");
  }
}

// Where the table first reaches the puncture force, linear between depths.
void InterpolateForceNetPunctureDepth(ForceNetModel& m) {
  const ForceNetDef& def = m.def;
  for (std::size_t k = 1; k < m.force_N.size(); ++k) {
    if (m.force_N[k] < def.puncture_force_N) continue;
    const double f = (def.puncture_force_N - m.force_N[k - 1]) / (m.force_N[k] - m.force_N[k - 1]);
    m.puncture_depth_m = (static_cast<double>(k - 1) + f) * def.table_step_m;
    break;
  }
}

}  // namespace

ForceNetDef ForceNetDefFor(const TissueLayer& layer) {
  ForceNetDef d;
  d.rings_w = layer.rings_w;
  d.spacing_L_m = layer.spacing_L_m;
  d.virtual_K_N_per_m = layer.virtual_K_N_per_m;
  d.puncture_force_N = layer.puncture_force_N;
  d.table_step_m = layer.spacing_L_m / 40.0;  // finer than the dimple's curvature; bounds the build on coarse nets
  return d;
}

ForceNetModel BuildForceNet(const ForceNetDef& def) {
  CheckForceNetDef(def);
  ForceNetModel m;
  m.def = def;
  m.topology = MakeHexNetTopology(def.rings_w, def.spacing_L_m);
  m.surface_k_N_per_m = def.surface_ratio * def.virtual_K_N_per_m;
  m.surface_rest_m = def.spacing_L_m / (1.0 + def.prestretch);
  MeasureForceNetLateralInfluence(m);
  TabulateForceNetDepths(m);
  RequireForceNet(m.static_residual_N < 1e-6,
                  "the static solve did not converge (residual " + std::to_string(m.static_residual_N) + " N)");
  InterpolateForceNetPunctureDepth(m);
  return m;
}

namespace {

// Table segment and fraction for a depth (clamped to the table).
std::pair<std::size_t, double> ForceNetTableAt(const ForceNetModel& m, double depth_m) {
  const double last = static_cast<double>(m.force_N.size() - 1);
  const double u = std::clamp(depth_m / m.def.table_step_m, 0.0, last);
  const auto k = static_cast<std::size_t>(std::min(std::floor(u), last - 1.0));
  return {k, u - static_cast<double>(k)};
}

}  // namespace

double NetForceAtDepth_N(const ForceNetModel& m, double depth_m) {
  const auto [k, f] = ForceNetTableAt(m, depth_m);
  return (1.0 - f) * m.force_N[k] + f * m.force_N[k + 1];
}

double NetStiffnessAtDepth_N_per_m(const ForceNetModel& m, double depth_m) {
  const auto [k, f] = ForceNetTableAt(m, depth_m);
  return (m.force_N[k + 1] - m.force_N[k]) / m.def.table_step_m;
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
  s.t1_W = normal_W.unitOrthogonal();
  s.t2_W = normal_W.cross(s.t1_W);
  const auto& off = model.topology.offset_T_m;
  for (Eigen::Index i = 0; i < off.cols(); ++i) s.rest_W_m.col(i) = n1_W_m + off(0, i) * s.t1_W + off(1, i) * s.t2_W;
  s.x_W_m = s.rest_W_m;
  s.ring_Z_m.setZero();
  s.depth_m = 0.0;
  s.anchored = true;
}

void SolveForceNet(const ForceNetModel& model, const Eigen::Vector3d& n1_now_W_m, ForceNetState& s) {
  const Eigen::Vector3d u1 = n1_now_W_m - s.n1_rest_W_m;
  const double along_n = u1.dot(s.normal_W);
  const Eigen::Vector3d lateral = u1 - along_n * s.normal_W;
  s.depth_m = std::max(0.0, -along_n);
  const auto [k, f] = ForceNetTableAt(model, s.depth_m);
  const Eigen::Matrix3Xd& a = model.displacement_T_m[k];
  const Eigen::Matrix3Xd& b = model.displacement_T_m[k + 1];
  for (Eigen::Index i = 0; i < s.x_W_m.cols(); ++i) {
    const Eigen::Vector3d d = (1.0 - f) * a.col(i) + f * b.col(i);
    s.x_W_m.col(i) = s.rest_W_m.col(i) + d.x() * s.t1_W + d.y() * s.t2_W + d.z() * s.normal_W +
                     model.lateral_influence[i] * lateral;
  }
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
