// Parameters of the `cutting` scene (SceneSpec::params, SI, units in the
// names): CuttingParamTable() declares each with its unit, range and
// description; defaults are CuttingParams{} — the cutting paper's skin
// (Table 1: E = 20 kPa, eps_r = 0.1; D lower, see below). One material:
// the springs are not a parameter but the membrane of E and the thickness
// (K = 3 E t / 8 = 15 N/m, where Table 1's K = 0.16 N/mm would be a skin of
// 213 kPa), and sigma_r = E eps_r is that membrane's pre-stress.
//
// Limits keep a cutting tick under a millisecond at the 99th percentile
// (bench_cutting_tick: 10k nodes, docs/performance.md): at most kMaxNodes
// grid nodes (docs/scene-limits.md).
#pragma once
#include <map>
#include <string>

#include "hapsim/core/scenes/param_table.h"

namespace hapsim::core {

struct CuttingLimits {
  static constexpr double kMaxNodes = 10500;  // grid nodes (length/spacing + 1)(width/spacing + 1)
};

struct CuttingParams {
  double patch_length_m = 0.06;          // abdominal skin patch, along x
  double patch_width_m = 0.04;           // along y
  double spacing_m = 0.0008;             // grid spacing: 76 x 51 = 3876 nodes
  double skin_thickness_m = 0.002;       // t: the wound face area is t x edge length
  // D per node. Table 1's D = 3 N*s/m applied to each node of this 0.8 mm
  // grid makes the wound's opening a creep of seconds with no overshoot
  // (docs/validation.md#cutting); 0.1 N*s/m gives the paper's Fig. 6 shape.
  double damping_Ns_per_m = 0.1;
  double node_mass_kg = 0.02;  // x14 000 real skin's: the explicit 1 ms step with the blade's damping
  // The tissue underneath: skin slides over it (a weak in-plane anchor per
  // node) but is held against pressing (a vertical support per node).
  double anchor_stiffness_N_per_m = 1.0;
  double support_stiffness_N_per_m = 50.0;
  double youngs_modulus_Pa = 20e3;           // E (Table 1)
  double residual_strain = 0.1;              // eps_r (Table 1): sigma_r = E eps_r
  double blade_radius_m = 4e-4;              // the scalpel as a cylinder (paper §2.2)
  double blade_length_m = 0.02;
  double sweep_radius_m = 0.001;             // stage 1's swept disc
  double segment_length_m = 0.0016;          // blade travel per incision segment
  double cut_depth_m = 5e-4;                 // tip this far below the surface starts an incision
  double contact_stiffness_N_per_m = 300.0;  // tip-skin penalty before the blade cuts
  double contact_damping_Ns_per_m = 0.5;
  double render_stiffness_max_N_per_m = 1500.0;  // cap on the stiffness sent to the device
  double cut_force_N = 0.3;                  // Coulomb level of the drag while cutting
  double cut_damping_Ns_per_m = 5.0;         // viscous part of the drag
  double max_kinetic_energy_J = 10.0;        // blow-up guard
  // Resting nodes (msm/resting_nodes.h): skin whose net force stays under
  // rest_force_N and speed under rest_speed_m_per_s is left out of the step
  // until something pulls it; 0 = every node every step. A resting patch is
  // held in the plane by its anchors alone, so it sits within ~rest_force /
  // anchor_stiffness (10 um) of the full step's skin: measured side by side
  // up to 1e-5 N (docs/validation.md), the parameter's limit.
  double rest_force_N = 1e-5;
  double rest_speed_m_per_s = 1e-4;
};

const ParamTable<CuttingParams>& CuttingParamTable();
// The table, then the cross-parameter rules (node count, sweep radius >=
// spacing and >= blade radius, segment length >= spacing).
CuttingParams ParseCuttingParams(const std::map<std::string, double>& params);

}  // namespace hapsim::core
