// Parameters of the `vessel` scene (SceneSpec::params, SI, units in the
// names): VesselParamTable() declares each with its unit, range and
// description; defaults are VesselParams{}.
//
// Geometry per shape (a dimension left at 0 takes the shape's default).
// Typical adult dimensions, rounded; sizes vary widely between people and
// sites, so these are representative, not patient data:
//   straight   hand dorsal vein  lumen radius 1.25 mm (2.5 mm diameter), wall 0.4 mm,
//                                length 30 mm, node spacing 0.5 mm
//   bent       aortic arch       lumen radius 12.5 mm (25 mm), wall 2 mm, a 180° arch of
//                                centreline radius 30 mm in a 134 mm length, spacing 3.2 mm
//   twice_bent retinal arteriole lumen radius 60 µm (120 µm), wall 20 µm, two opposite
//                                60° bends of radius 0.5 mm in 3 mm, spacing 35 µm
#pragma once
#include <map>
#include <string>

#include "hapsim/core/scenes/param_table.h"
#include "hapsim/core/scenes/vessel/vessel_geometry.h"

namespace hapsim::core {

struct VesselLimits {
  // Meshless nodes a 1 kHz tick can afford (docs/scene-limits.md).
  // ~0.8 ms per tick at this size with the probe crushing the vein (1 substep): docs/scene-limits.md#vessel.
  static constexpr double kMaxNodes = 5200;
};

// The wall's model: the paper's and its two baselines on the same nodes.
enum class VesselModel : int {
  kMeshlessXpbd = 0,  // meshless elasticity + XPBD stretching constraints (the paper's)
  kMassSpring = 1,    // springs on the lattice's edges and diagonals, k = E x rest length
  kPlainPbd = 2,      // plain PBD distance constraints on the same springs, stiffness pbd_stiffness
};

struct VesselParams {
  int model = 0;                      // VesselModel
  int shape = 0;                      // 0 straight (dorsal vein), 1 bent (aortic arch), 2 twice bent (retinal)
  double length_m = 0.0;              // 0: the shape's default
  double lumen_radius_m = 0.0;
  double wall_thickness_m = 0.0;
  double node_spacing_m = 0.0;
  int radial_layers = 2;
  double youngs_modulus_Pa = 1e5;     // E of the wall
  double poisson_ratio = 0.45;        // nearly incompressible soft tissue
  double density_kg_per_m3 = 1050.0;
  // Node masses are density x volume x this (0: automatic, the smallest
  // scale at which the explicit meshless step is stable with a margin of 2;
  // ~9800 for the vein at 1 substep, ~2500 at 2). The meshless forces are
  // explicit: real wall masses would need ~100 sub-steps per millisecond. Statics
  // (force against displacement) do not depend on it; the wall's dynamics
  // are slower by its square root.
  double mass_scale = 0.0;
  double support_radius_factor = 1.6;  // h = factor x node spacing (~14 neighbours on a 2-layer wall)
  // Physics steps per tick. 1: a 5k-node vein ticks in ~0.5 ms (2: ~1 ms,
  // over a 1 kHz tick's budget); settled forces agree within 1 % between
  // 1 and 2 (docs/validation.md#vessel), the heavier scaled masses of 1 make
  // the wall's dynamics slower.
  int substeps = 1;
  int xpbd_iterations = 1;             // constraint sweeps per step (XPBD: statics do not depend on it)
  // Stretching constraints (paper §2.2.1) between lattice neighbours, with
  // stiffness fraction x E x spacing (XPBD compliance = its inverse).
  double stretch_fraction = 0.2;
  // The paper's elastic-potential-energy constraints (§2.2.2): six virtual
  // tetrahedra per lattice cell, springs on their edges with stiffness
  // fraction x E x spacing (0: off, the default — the meshless forces carry
  // the elasticity; on at 0.2 they add ~0.8 ms per tick on the vein's 6480
  // tetrahedra, more than the tick affords).
  double tet_fraction = 0.0;
  double pbd_stiffness = 0.2;          // plain-PBD baseline: projection scale k in (0, 1] per sweep
  // Mass-proportional velocity damping. 15/s on the 1-substep masses is the
  // drag per velocity 60/s gave on the 2-substep ones (4x lighter); pressed
  // at 10 mm/s the vein's force at 1 mm is then 1.4x its settled value.
  double damping_per_s = 15.0;
  // The tissue the vessel lies in (skin and subcutis over it, connective
  // tissue around it) as an elastic (Winkler) foundation: each outer-wall
  // node is tied to its rest position by a spring of E_t x (its share of the
  // outer surface) / depth. It keeps the vessel from rolling away under the
  // probe (a vein on a frictionless bed slid 3 mm sideways and let a probe
  // through at 1.6 mm) and is most of what a finger or probe on the skin
  // feels. E_t: in vivo skin ~69 kPa (Hendriks et al. 2006); depth 0: the
  // outer radius. 0: no foundation (the bare tube on its bed).
  double tissue_modulus_Pa = 69e3;
  double tissue_depth_m = 0.0;
  // The skin and subcutis the probe itself indents over and beside the
  // vessel, in parallel with the vessel under it: an elastic half-space of
  // the same tissue (E_t, incompressible) whose surface is the level plane
  // through the vessel's top, pressed by the probe's sphere (Hertz) and,
  // once the sphere is in, by its shaft (a flat punch of the same radius;
  // the force and its slope are continuous). 1 on, 0 off, -1 the shape's
  // default (on for the straight hand vein, which lies under the skin).
  int skin = -1;
  // Blood pressure in the lumen [Pa], on the inner wall (a follower load
  // along the current normals); the wall is inflated to it at build and
  // resets to that state. A hand vein at heart level: ~0.7 kPa (7.2 cmH2O);
  // under a venipuncture tourniquet ~70-80 % of the cuff's pressure (J Clin
  // Anesth 2007, dorsal hand vein), ~6 kPa under the recommended 60 mmHg
  // (Sasaki et al. 2012) — the default: the vein a trainee palpates before
  // a cannulation.
  double lumen_pressure_Pa = 6000.0;
  double probe_radius_m = 1e-3;        // catheter / probe tip as a sphere
  // Coulomb friction between the probe and the tissue (skin on steel or
  // plastic: ~0.2-0.8 in the literature, e.g. Derler & Gerhardt 2012). Without
  // it, the wall pressed deep slides round the sphere and lets the probe through.
  double contact_friction = 0.5;
  double contact_stiffness_N_per_m = 2000.0;  // XPBD compliance of the tip-node contact = its inverse
  double render_stiffness_max_N_per_m = 1000.0;
  double max_kinetic_energy_J = 1.0;   // a step above this is a blow-up: counted, the scene resets
  // The wall sleeps — its step is skipped, its state kept — once every node
  // has moved slower than this for kQuietStepsToSleep steps while the tip
  // stood still or touched nothing; it wakes when the probe sphere reaches a
  // node, or when the tip moves or the tool is lost in a contact. 0: the full
  // step every tick. The error against the full step: docs/validation.md#vessel.
  double rest_speed_m_per_s = 1e-5;
};

const ParamTable<VesselParams>& VesselParamTable();
// The table, then the shape defaults and the node-count limit.
VesselParams ParseVesselParams(const std::map<std::string, double>& params);
// The generator's definition for these parameters (shape defaults applied).
VesselGeometryDef VesselGeometryFor(const VesselParams& params);

}  // namespace hapsim::core
