// The acupuncture paper's mass-spring force net (§3.2), solved with the MSM
// core. Built when the needle touches a layer: particles on concentric
// hexagonal rings in the tangent plane at the contact point N1, surface
// springs between lattice neighbours, and per particle a "virtual spring"
// (stiffness K) to its rest position that stands for the tissue underneath.
// N1 follows the needle tip; every other particle is in static equilibrium.
//
// [decide] How Z_j falls off with ring j (MISSION.md §1) — the net's springs
// decide it. Skin in vivo is under tension; a surface spring at rest length
// L would have no transverse stiffness at all (a press would stay on N1), so
// the surface springs are tensioned: zero rest length and stiffness
// k_s = tension_ratio·K, i.e. tension k_s·L at the lattice spacing, held at
// the net's rim by the surrounding skin (a constant edge traction that makes
// the rest lattice an equilibrium). The virtual springs are zero-length
// anchors (K in every direction; along the normal they are the paper's
// springs). All forces are then linear in the positions, so the static
// solution is N1's displacement times a fixed influence vector g (g_0 = 1):
// BuildForceNet solves the MSM statics once (backward Euler to equilibrium),
// and each tick costs O(n) with no solver iterations. Static equilibrium of
// all particles but N1 makes the reaction on the tip exactly
//   F·n = K Z_1 + K Σ_{j=2..w} 6(j-1) Z_j      (paper eq. 6)
// with Z_j the mean inward deflection of ring j.
//
// Puncture (paper: "when the deformation reaches ring w"): ring w counts as
// deformed once Z_w >= ζ = threshold_ratio·L. Since Z_w = g_w Z_1 this is a
// critical deflection Z_1* = ζ / g_w and a peak force K (Σ g) Z_1*.
#pragma once
#include <Eigen/Core>

#include "hapsim/core/needle/hex_net_topology.h"
#include "hapsim/core/needle/tissue_layers.h"

namespace hapsim::core {

struct ForceNetDef {
  int rings_w = 8;                     // w
  double spacing_L_m = 2e-3;           // L
  double virtual_K_N_per_m = 160.0;    // K (Table 2: 0.16 N/mm for skin)
  double tension_ratio = 30.0;         // k_s / K of the surface springs
  double threshold_ratio = 0.02;       // ζ / L: ring w "deformed" at Z_w >= ζ
};

struct ForceNetModel {
  ForceNetDef def;
  HexNetTopology topology;
  double surface_k_N_per_m = 0.0;   // k_s = tension_ratio·K
  double threshold_m = 0.0;         // ζ
  Eigen::VectorXd influence;        // g_i: displacement of node i per unit N1 displacement (n), g_0 = 1
  Eigen::VectorXd ring_influence;   // mean g over ring j (w): Z_j = ring_influence[j-1]·Z_1
  double influence_sum = 0.0;       // Σ g_i: normal stiffness at N1 is K·Σ g_i
  double critical_deflection_m = 0.0;  // Z_1* = ζ / g_w
  double static_residual_N = 0.0;   // max |force| on a free node after the MSM solve (check)
};

// The net of one tissue layer: its rings w, spacing L and virtual K (Table 2),
// with the default tension and threshold ratios.
ForceNetDef ForceNetDefFor(const TissueLayer& layer);

// Validates def (throws std::invalid_argument naming the field) and solves
// the statics with the MSM core (allocates; call at scene build).
ForceNetModel BuildForceNet(const ForceNetDef& def);

// A net placed on a surface, mutable per tick.
struct ForceNetState {
  Eigen::Vector3d n1_rest_W_m = Eigen::Vector3d::Zero();  // N1 where the needle touched
  Eigen::Vector3d normal_W = Eigen::Vector3d::UnitZ();    // outward surface normal at N1
  Eigen::Matrix3Xd rest_W_m;    // rest particle positions (3 x n)
  Eigen::Matrix3Xd x_W_m;       // current particle positions (3 x n)
  Eigen::VectorXd ring_Z_m;     // Z_j: mean inward (along -normal) deflection of ring j (w)
  bool anchored = true;         // virtual springs present (removed at puncture)
};

// Sized for the model (allocates once).
ForceNetState MakeForceNetState(const ForceNetModel& model);

// Places the net in the tangent plane at n1 with outward normal (unit), at
// rest and anchored. Never allocates.
void PlaceForceNet(const ForceNetModel& model, const Eigen::Vector3d& n1_W_m, const Eigen::Vector3d& normal_W,
                   ForceNetState& state);

// Static solution with N1 moved to n1_now_W_m (the needle tip): x_i = rest_i
// + g_i·(n1_now - n1_rest); updates ring_Z_m. Never allocates.
void SolveForceNet(const ForceNetModel& model, const Eigen::Vector3d& n1_now_W_m, ForceNetState& state);

// Recomputes ring_Z_m from x_W_m (after springback moved the particles).
void UpdateRingDeflections(const ForceNetModel& model, ForceNetState& state);

// Force the net exerts on the needle tip [N]: the sum of every virtual
// spring's pull, -K Σ (x_i - rest_i) (equal to the springs' pull on N1 in
// static equilibrium). Zero once unanchored.
Eigen::Vector3d NetReactionOnTip_W_N(const ForceNetModel& model, const ForceNetState& state);

// Paper eq. (6) from ring deflections: K Z_1 + K Σ_{j>=2} 6(j-1) Z_j [N].
double PaperSurfaceForce_N(const ForceNetModel& model, const Eigen::VectorXd& ring_Z_m);

// "The deformation has reached ring w": Z_w >= ζ.
inline bool DeformationReachedRingW(const ForceNetModel& model, const ForceNetState& state) {
  return state.ring_Z_m[state.ring_Z_m.size() - 1] >= model.threshold_m;
}

}  // namespace hapsim::core
