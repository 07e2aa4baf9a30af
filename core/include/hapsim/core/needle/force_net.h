// The acupuncture paper's mass-spring force net (§3.2), solved with the MSM
// core. Built when the needle touches a layer: particles on concentric
// hexagonal rings in the tangent plane at the contact point N1, surface
// springs between lattice neighbours, and per particle a "virtual spring"
// (stiffness K) to its rest position that stands for the tissue underneath.
// N1 follows the needle tip; every other particle is in static equilibrium.
//
// Surface springs have a finite rest length — the paper's "L is the length
// of the surface spring" — with a small pre-stretch: their rest length is
// L / (1 + prestretch) and the rest lattice (spacing L) is held in
// equilibrium by a constant traction on the rim (the skin around the net).
// Pressed, the net stretches and stiffens: the force rises J-shaped with
// depth, like skin, and the dimple spreads over millimetres. The statics are
// nonlinear, so BuildForceNet solves them with the MSM core's backward Euler
// (long steps = Newton steps on the statics) at depths 0, Δ, 2Δ, … and
// tabulates every particle's displacement; a tick interpolates the table
// (O(n), no solver). Lateral motion of N1 uses the linear influence of an
// in-plane displacement at rest.
//
// Static equilibrium of all particles but N1 makes the reaction on the tip
//   F = -K Σ (x_i - rest_i),  so F·n = K Z_1 + K Σ_{j=2..w} 6(j-1) Z_j
// (paper eq. 6, with Z_j the mean inward deflection of ring j) for any
// displacement field: the equation is the count of particles per ring, not
// a check of the solve. The solve is checked against an independent one
// (tests/validation/check_puncture.py, force_net_test.cpp).
//
// Puncture — a departure from "the deformation has reached ring w": the
// layer is pierced when the force on the tip reaches its puncture force
// (a per-layer property of tissue and needle, docs/validation.md).
#pragma once
#include <vector>

#include <Eigen/Core>

#include "hapsim/core/needle/hex_net_topology.h"
#include "hapsim/core/needle/tissue_layers.h"

namespace hapsim::core {

struct ForceNetDef {
  int rings_w = 8;                     // w
  double spacing_L_m = 2e-3;           // L
  double virtual_K_N_per_m = 160.0;    // K (Table 2: 0.16 N/mm for skin)
  double surface_ratio = 1.0;          // k_s / K of the surface springs
  double prestretch = 0.02;            // L / rest length - 1 of the surface springs
  double puncture_force_N = 1.0;       // the layer is pierced at this normal force on the tip
  double table_step_m = 5e-5;          // Δ: depth between two tabulated solves (ForceNetDefFor: L / 40)
  double table_max_depth_m = 0.02;     // tabulate at most this deep (reached only by a large puncture force)
};

struct ForceNetModel {
  ForceNetDef def;
  HexNetTopology topology;
  double surface_k_N_per_m = 0.0;   // k_s
  double surface_rest_m = 0.0;      // L / (1 + prestretch)
  // Table over depth d_k = k Δ (k = 0 … size-1): displacement of every
  // particle in the net's frame (rows: along t1, t2, outward normal), and
  // the normal force on the tip F_k = -K Σ u_n.
  std::vector<Eigen::Matrix3Xd> displacement_T_m;
  std::vector<double> force_N;
  Eigen::VectorXd lateral_influence;  // in-plane displacement of each particle per unit lateral N1 motion (n)
  double lateral_stiffness_N_per_m = 0.0;  // K Σ lateral_influence
  double puncture_depth_m = 0.0;    // where F reaches puncture_force_N (interpolated)
  double static_residual_N = 0.0;   // max |force| on a free particle over the table's solves
  int newton_steps = 0;             // backward-Euler steps the build took (all depths)
};

// The net of one tissue layer: its rings w, spacing L, virtual K (Table 2)
// and puncture force, with the default surface ratio and pre-stretch.
ForceNetDef ForceNetDefFor(const TissueLayer& layer);

// Validates def (throws std::invalid_argument naming the field) and solves
// the statics with the MSM core (allocates; call at scene build). Throws if
// the puncture force is not reached within table_max_depth_m.
ForceNetModel BuildForceNet(const ForceNetDef& def);

// Normal force on the tip [N] and its slope dF/dd [N/m] at depth d (clamped
// to the table; linear interpolation).
double NetForceAtDepth_N(const ForceNetModel& model, double depth_m);
double NetStiffnessAtDepth_N_per_m(const ForceNetModel& model, double depth_m);

// A net placed on a surface, mutable per tick.
struct ForceNetState {
  Eigen::Vector3d n1_rest_W_m = Eigen::Vector3d::Zero();  // N1 where the needle touched
  Eigen::Vector3d normal_W = Eigen::Vector3d::UnitZ();    // outward surface normal at N1
  Eigen::Vector3d t1_W = Eigen::Vector3d::UnitX(), t2_W = Eigen::Vector3d::UnitY();  // the net's tangent frame
  Eigen::Matrix3Xd rest_W_m;    // rest particle positions (3 x n)
  Eigen::Matrix3Xd x_W_m;       // current particle positions (3 x n)
  Eigen::VectorXd ring_Z_m;     // Z_j: mean inward (along -normal) deflection of ring j (w)
  double depth_m = 0.0;         // N1's depth below its rest position (>= 0)
  bool anchored = true;         // virtual springs present (removed at puncture)
};

// Sized for the model (allocates once).
ForceNetState MakeForceNetState(const ForceNetModel& model);

// Places the net in the tangent plane at n1 with outward normal (unit), at
// rest and anchored. Never allocates.
void PlaceForceNet(const ForceNetModel& model, const Eigen::Vector3d& n1_W_m, const Eigen::Vector3d& normal_W,
                   ForceNetState& state);

// Static solution with N1 moved to n1_now_W_m (the needle tip): the table
// at N1's depth plus the lateral influence of its in-plane offset; updates
// depth_m and ring_Z_m. Never allocates.
void SolveForceNet(const ForceNetModel& model, const Eigen::Vector3d& n1_now_W_m, ForceNetState& state);

// Recomputes ring_Z_m from x_W_m (after springback moved the particles).
void UpdateRingDeflections(const ForceNetModel& model, ForceNetState& state);

// Force the net exerts on the needle tip [N]: the sum of every virtual
// spring's pull, -K Σ (x_i - rest_i) (equal to the springs' pull on N1 in
// static equilibrium). Zero once unanchored.
Eigen::Vector3d NetReactionOnTip_W_N(const ForceNetModel& model, const ForceNetState& state);

// Paper eq. (6) from ring deflections: K Z_1 + K Σ_{j>=2} 6(j-1) Z_j [N].
double PaperSurfaceForce_N(const ForceNetModel& model, const Eigen::VectorXd& ring_Z_m);

// The layer gives way: the normal force on the tip has reached the puncture force.
inline bool PunctureForceReached(const ForceNetModel& model, const ForceNetState& state) {
  return state.anchored && NetReactionOnTip_W_N(model, state).dot(state.normal_W) >= model.def.puncture_force_N;
}

}  // namespace hapsim::core
