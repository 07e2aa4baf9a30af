// Parameters of the `tissue_block` scene (SceneSpec::params, SI, units in
// the names): one table, TissueBlockParamTable(), declares each with its
// unit, range, description and (through TissueBlockParams) default.
//
// Cost limits (docs/scene-limits.md): grid_nodes <= 101, dt_s >= 1e-6 s and
// TissueBlockStepCost() <= kMaxStepCost, so a client cannot ask for a tick
// that takes more than ~0.3 ms of CPU. Backward Euler runs at most
// kMaxCgIterations conjugate-gradient iterations per sub-step (the default
// tissue converges in ~10); a stiffer system gets the truncated solve.
#pragma once
#include <map>
#include <string>

#include "hapsim/core/msm/integrator_kind.h"
#include "hapsim/core/msm/units.h"
#include "hapsim/core/scenes/param_table.h"

namespace hapsim::core {

struct TissueBlockParams {
  int grid_nodes = 21;                      // nodes per side, [3, 101]
  double size_m = 0.06;                     // side length of the patch [m]
  // Skin spring stiffness of the acupuncture/cutting papers, K = 0.16 N/mm.
  double spring_stiffness_N_per_m = units::NPerMmToNPerM(0.16);
  double shear_stiffness_N_per_m = units::NPerMmToNPerM(0.16);
  double spring_damping_Ns_per_m = 0.02;    // along each surface spring
  // Per-node anchor: with the defaults a 5 mm press gives about 1 N.
  double anchor_stiffness_N_per_m = 40.0;
  double damping_Ns_per_m = 0.5;            // per node, absolute (substrate drag)
  double node_mass_kg = 2.5e-3;              // lumped; sets the explicit critical step
  double prestretch = 0.05;                 // rest length = spacing / (1 + prestretch)
  double contact_stiffness_N_per_m = 1000.0;  // needle-surface penalty
  // Penalty damper on the penetration rate: without it the light surface
  // nodes bounce off the tip and contact chatters on first touch.
  double contact_damping_Ns_per_m = 0.8;
  double max_penetration_m = 0.02;          // deeper tips are treated as this deep
  double dt_s = 1e-3;                       // largest internal step; Step() sub-steps to it
  IntegratorChoice integrator{};            // default symplectic Euler
  int local_update_hops = 0;                // 0 = full update every step
  // Out of contact, once every node is within this of its rest position
  // (each coordinate) and slower than this x sqrt(anchor_stiffness /
  // node_mass), the block is put at rest and its steps are skipped until the
  // tool touches it again. 0: the full step every tick. [m], [0, 1e-6]
  double rest_displacement_m = 1e-7;
  // Stability guard: a step above this kinetic energy counts as a blow-up
  // and resets the scene. The patch never gets near 10 J under a hand.
  double max_kinetic_energy_J = 10.0;
};

// What a client may ask for, so that a build takes milliseconds and one 1 ms
// Step() at most ~0.3 ms of CPU (measured: docs/scene-limits.md).
struct TissueBlockLimits {
  static constexpr int kMaxGridNodes = 101;
  // 1000 sub-steps per 1 ms tick; Step() never runs more (kMaxSubsteps).
  static constexpr double kMinDt_s = 1e-6;
  // At most this many sub-steps per Step(): a huge dt (e.g. after a pause)
  // is truncated instead of stalling the tick.
  static constexpr int kMaxSubsteps = 1000;
  static constexpr int kMaxCgIterations = 20;  // backward Euler, per sub-step
  // Budget for TissueBlockStepCost(): 1 unit ~ 13 ns here; the worst
  // accepted combinations measured p50 <= 0.17 ms, p99 <= 0.19 ms.
  static constexpr double kMaxStepCost = 12000.0;
};

// Estimated CPU cost of one 1 ms Step() in node updates (one node through
// one symplectic Euler sub-step):
//   grid_nodes^2 x ceil(1 ms / dt_s) x integrator factor
//   (explicit 1.5, symplectic 1, improved 1.5, midpoint 2.5, RK4 5,
//    backward Euler 4 + 1.1 per CG iteration = 26),
// with local_update_hops > 0 times 1.15 (indexed node lists; a step out of
// contact still updates every node) plus 8 per node of the region
// re-selected when the contact moves (at most once per Step()).
double TissueBlockStepCost(const TissueBlockParams& params);

// The scene's parameter table (defaults: TissueBlockParams{}).
const ParamTable<TissueBlockParams>& TissueBlockParamTable();

// Parses params with the table, then the cross-parameter step-cost limit;
// unknown keys and bad values throw std::invalid_argument naming the key(s)
// and the allowed range.
TissueBlockParams ParseTissueBlockParams(const std::map<std::string, double>& params);

}  // namespace hapsim::core
