#include "hapsim/core/scenes/tissue_block/tissue_block_params.h"

#include <algorithm>
#include <cmath>
#include <sstream>
#include <stdexcept>

namespace hapsim::core {
namespace {

static_assert(TissueBlockLimits::kMaxSubsteps * TissueBlockLimits::kMinDt_s >= 1e-3,
              "a 1 ms Step() must never be truncated");
// The tick the cost limit is stated for [s] (the server's 1 kHz period).
constexpr double kReferenceTick_s = 1e-3;

// Cost of one node through one sub-step relative to symplectic Euler,
// measured on the tissue grid (docs/scene-limits.md). Backward Euler: a
// setup of ~4 plus ~1.1 per CG iteration, at the iteration cap.
constexpr double kBackwardEulerCost = 4.0 + 1.1 * TissueBlockLimits::kMaxCgIterations;
double IntegratorCost(IntegratorKind kind) {
  switch (kind) {
    case IntegratorKind::kExplicitEuler: return 1.5;
    case IntegratorKind::kSymplecticEuler: return 1.0;
    case IntegratorKind::kImprovedEuler: return 1.5;
    case IntegratorKind::kMidpointAveraging: return 2.5;
    case IntegratorKind::kRk4: return 5.0;
    case IntegratorKind::kBackwardEuler: return kBackwardEulerCost;
  }
  return kBackwardEulerCost;  // unreachable: the most expensive
}
// Local update: integrating through node/spring index lists costs ~15 % more
// per node, and re-selecting a region ~8 node updates per region node (BFS,
// sorts).
constexpr double kLocalUpdateOverhead = 1.15;
constexpr double kRegionSelectCostPerNode = 8.0;

void CheckStepCost(const TissueBlockParams& p) {
  const double cost = TissueBlockStepCost(p);
  if (cost <= TissueBlockLimits::kMaxStepCost) return;
  std::ostringstream msg;
  msg << "tissue_block: parameters 'grid_nodes' = " << p.grid_nodes << ", 'dt_s' = " << p.dt_s
      << " s, 'integrator' = " << ToString(p.integrator.kind) << " and 'local_update_hops' = " << p.local_update_hops
      << " would cost about " << static_cast<long long>(cost) << " node updates per 1 ms step; the limit is "
      << TissueBlockLimits::kMaxStepCost
      << " (about 0.3 ms of CPU). Cost = grid_nodes^2 x ceil(0.001 s / dt_s) x integrator factor (explicit_euler "
         "1.5, symplectic_euler 1, improved_euler 1.5, midpoint_averaging 2.5, rk4 5, backward_euler "
      << kBackwardEulerCost << "), with "
         "local_update_hops > 0 x 1.15 + 8 x min(grid_nodes^2, (2 local_update_hops + 1)^2). Use fewer grid_nodes, "
         "a larger dt_s or a cheaper integrator (docs/scene-limits.md)";
  throw std::invalid_argument(msg.str());
}

ParamTable<TissueBlockParams> MakeTissueBlockTable() {
  using P = TissueBlockParams;
  ParamTable<P> t("tissue_block");
  std::vector<std::string> integrators;
  for (int code = 0; code < kNumIntegratorKinds; ++code) integrators.push_back(ToString(static_cast<IntegratorKind>(code)));
  t.Add({.name = "grid_nodes",
         .unit = "count",
         .min = 3,
         .max = TissueBlockLimits::kMaxGridNodes,
         .integer = true,
         .description = "nodes per side of the square surface grid"},
        &P::grid_nodes)
      .Add({.name = "size_m", .unit = "m", .min = 0, .min_open = true, .description = "side length of the patch"},
           &P::size_m)
      .Add({.name = "spring_stiffness_N_per_m",
            .unit = "N/m",
            .min = 0,
            .description = "stiffness of the structural (grid-edge) surface springs"},
           &P::spring_stiffness_N_per_m)
      .Add({.name = "shear_stiffness_N_per_m",
            .unit = "N/m",
            .min = 0,
            .description = "stiffness of the shear (cell-diagonal) surface springs"},
           &P::shear_stiffness_N_per_m)
      .Add({.name = "spring_damping_Ns_per_m",
            .unit = "N*s/m",
            .min = 0,
            .description = "damping along each surface spring"},
           &P::spring_damping_Ns_per_m)
      .Add({.name = "anchor_stiffness_N_per_m",
            .unit = "N/m",
            .min = 0,
            .min_open = true,
            .description = "zero-length spring tying each node to its rest position (the tissue underneath)"},
           &P::anchor_stiffness_N_per_m)
      .Add({.name = "damping_Ns_per_m", .unit = "N*s/m", .min = 0, .description = "absolute drag on every node"},
           &P::damping_Ns_per_m)
      .Add({.name = "node_mass_kg",
            .unit = "kg",
            .min = 0,
            .min_open = true,
            .description = "lumped mass of each node (sets the explicit critical step)"},
           &P::node_mass_kg)
      .Add({.name = "prestretch",
            .unit = "1",
            .min = 0,
            .max = 1,
            .max_open = true,
            .description = "surface springs' rest length = spacing / (1 + prestretch)"},
           &P::prestretch)
      .Add({.name = "contact_stiffness_N_per_m",
            .unit = "N/m",
            .min = 0,
            .min_open = true,
            .description = "needle-surface penalty spring"},
           &P::contact_stiffness_N_per_m)
      .Add({.name = "contact_damping_Ns_per_m",
            .unit = "N*s/m",
            .min = 0,
            .description = "penalty damper on the penetration rate"},
           &P::contact_damping_Ns_per_m)
      .Add({.name = "max_penetration_m",
            .unit = "m",
            .min = 0,
            .min_open = true,
            .description = "deeper tips are treated as this deep"},
           &P::max_penetration_m)
      .Add({.name = "dt_s",
            .unit = "s",
            .min = TissueBlockLimits::kMinDt_s,
            .description = "largest internal step; a tick sub-steps to it (also bounded by the critical step)"},
           &P::dt_s)
      .Add(
          {.name = "integrator",
           .unit = "code",
           .min = 0,
           .max = kNumIntegratorKinds - 1,
           .integer = true,
           .description = "time integrator",
           .choices = integrators},
          [](const P& p) { return static_cast<double>(p.integrator.kind); },
          [](P& p, double v) { p.integrator.kind = *IntegratorFromCode(v); })
      .Add(
          {.name = "midpoint_alpha",
           .unit = "1",
           .min = 0,
           .max = 1,
           .min_open = true,
           .description = "weight alpha of midpoint averaging (integrator 3)"},
          [](const P& p) { return p.integrator.alpha; }, [](P& p, double v) { p.integrator.alpha = v; })
      .Add({.name = "local_update_hops",
            .unit = "count",
            .min = 0,
            .max = 1000,
            .integer = true,
            .description = "0: integrate every node; N: in contact, only nodes within N spring hops (gingival paper)"},
           &P::local_update_hops)
      .Add({.name = "rest_displacement_m",
            .unit = "m",
            .min = 0,
            .max = 1e-6,
            .description = "out of contact, within this of rest (and slower than it x sqrt(anchor_stiffness / "
                           "node_mass)) the block is put at rest and sleeps until touched; 0: the full step always"},
           &P::rest_displacement_m)
      .Add({.name = "max_kinetic_energy_J",
            .unit = "J",
            .min = 0,
            .min_open = true,
            .description = "a step above this kinetic energy is a blow-up: counted, and the scene resets"},
           &P::max_kinetic_energy_J);
  return t;
}

}  // namespace

const ParamTable<TissueBlockParams>& TissueBlockParamTable() {
  static const ParamTable<TissueBlockParams> table = MakeTissueBlockTable();
  return table;
}

TissueBlockParams ParseTissueBlockParams(const std::map<std::string, double>& params) {
  const TissueBlockParams p = TissueBlockParamTable().Parse(params);
  CheckStepCost(p);
  return p;
}

double TissueBlockStepCost(const TissueBlockParams& p) {
  const double nodes = static_cast<double>(p.grid_nodes) * p.grid_nodes;
  const double substeps = std::min<double>(TissueBlockLimits::kMaxSubsteps, std::ceil(kReferenceTick_s / p.dt_s));
  const double integrate = nodes * substeps * IntegratorCost(p.integrator.kind);
  if (p.local_update_hops == 0) return integrate;
  const double side = 2.0 * p.local_update_hops + 1.0;  // shear springs: hops reach a square
  return kLocalUpdateOverhead * integrate + kRegionSelectCostPerNode * std::min(nodes, side * side);
}

}  // namespace hapsim::core
