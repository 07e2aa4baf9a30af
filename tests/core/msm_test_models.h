// Small hand-built MSM models, and the integrator list, shared by the MSM
// tests.
#pragma once
#include <string>

#include "hapsim/core/msm/integrator_kind.h"
#include "hapsim/core/msm/msm_model.h"

namespace hapsim::core::test {

// Every integrator, midpoint-averaging at the paper's three weights.
inline constexpr IntegratorChoice kAllMethods[] = {
    {IntegratorKind::kExplicitEuler, 0.5},     {IntegratorKind::kSymplecticEuler, 0.5},
    {IntegratorKind::kImprovedEuler, 0.5},     {IntegratorKind::kMidpointAveraging, 0.5},
    {IntegratorKind::kMidpointAveraging, 0.375}, {IntegratorKind::kMidpointAveraging, 0.625},
    {IntegratorKind::kRk4, 0.5},               {IntegratorKind::kBackwardEuler, 0.5},
};

// "midpoint_averaging alpha 0.375", "rk4", ...
inline std::string Name(IntegratorChoice m) {
  std::string name = ToString(m.kind);
  if (m.kind == IntegratorKind::kMidpointAveraging) name.append(" alpha ").append(std::to_string(m.alpha));
  return name;
}

// One free node of mass m on a zero-length anchor spring k (and damper c) at
// the origin: the linear oscillator m x'' = -k x - c x' in each axis.
inline MsmModel AnchoredNode(double m_kg, double k_N_per_m, double c_Ns_per_m = 0.0) {
  MsmDef d;
  d.x0_m = Eigen::Matrix3Xd::Zero(3, 1);
  d.mass_kg = Eigen::VectorXd::Constant(1, m_kg);
  d.anchor_node = {0};
  d.anchor_point_W_m = Eigen::Matrix3Xd::Zero(3, 1);
  d.anchor_k_N_per_m = {k_N_per_m};
  d.anchor_c_Ns_per_m = {c_Ns_per_m};
  return BuildMsmModel(d);
}

// A small irregular 3-D net: 5 nodes, 7 springs of different stiffness and
// rest length (some stretched, some compressed at x0), one anchor, gravity.
inline MsmDef IrregularNetDef() {
  MsmDef d;
  d.x0_m.resize(3, 5);
  d.x0_m << 0.000, 0.011, 0.002, 0.013, 0.006,  //
      0.000, 0.001, 0.012, 0.010, 0.005,        //
      0.000, 0.002, -0.001, 0.003, 0.008;
  d.mass_kg = Eigen::VectorXd::LinSpaced(5, 1e-3, 3e-3);
  d.node_damping_Ns_per_m = Eigen::VectorXd::Constant(5, 0.1);
  d.gravity_m_per_s2 = {0.0, 0.0, -9.81};
  d.springs = {{0, 1}, {0, 2}, {1, 3}, {2, 3}, {0, 4}, {1, 4}, {3, 4}};
  d.spring_rest_m = {0.010, 0.013, 0.009, 0.012, 0.008, 0.011, 0.010};
  d.spring_k_N_per_m = {160, 120, 200, 90, 150, 110, 130};
  d.spring_c_Ns_per_m = {0.01, 0.02, 0.0, 0.03, 0.01, 0.0, 0.02};
  d.anchor_node = {2};
  d.anchor_point_W_m = Eigen::Matrix3Xd::Zero(3, 1);
  d.anchor_point_W_m.col(0) << 0.001, 0.013, 0.0;
  d.anchor_k_N_per_m = {50.0};
  d.fixed = {1, 0, 0, 0, 0};
  d.spring_capacity = 10;
  d.max_node_degree = 6;
  return d;
}

}  // namespace hapsim::core::test
