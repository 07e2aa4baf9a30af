// The cutting paper's skin: a flat triangulated mass-spring patch in the
// z = 0 plane (outward normal +z), anchored underneath, which the cutter
// (skin_cutter.h) edits. One node per mesh vertex slot (node i = vertex i),
// so the MSM state's positions are the displayed vertices. Rest positions
// (MsmModel::x0_m) stay in the plane: every cut is planned there.
//
// Springs of the build: grid edges and both cell diagonals (structural and
// shear, K each), and two-apart neighbours along x and y (bending, k_b).
// With k_b = K / 4 the lattice is an isotropic membrane: nu = 1/3 and
// E t = 8 K / 3 (LatticeSpringStiffness_N_per_m).
//
// Pre-stress: living skin is under tension where it lies. Every spring's rest
// length is its drawn length times (1 - prestrain), so the drawn patch
// carries a uniform tension; hold_N (the tissue beyond the patch and the
// lattice's irregularities) balances each node's springs at its rest
// position, so the uncut patch is at rest as drawn. A cut removes springs:
// the lip nodes lose their pull across the wound (ApplyResidualStress gives
// them the exact face traction) while the springs along the lips keep their
// tension, so the wound opens as a stretched membrane does, with no
// compression along its lips (which folds a lattice).
// Node masses are lumped from an areal density (a third of each adjacent
// triangle's rest area), so the patch's total mass is density x area and
// stays so through cuts (the cutter re-lumps the nodes it touches).
#pragma once
#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "hapsim/core/mesh/mesh_topology.h"
#include "hapsim/core/msm/msm_model.h"
#include "hapsim/core/msm/msm_state.h"

namespace hapsim::core {

struct SkinDef {
  double length_m = 0.06;                  // along x
  double width_m = 0.04;                   // along y
  double spacing_m = 0.0008;               // grid spacing h
  double spring_k_N_per_m = 160.0;         // K = 0.16 N/mm (cutting paper, Table 1)
  double bending_k_N_per_m = 40.0;         // two-apart springs
  double spring_c_Ns_per_m = 0.0;          // along-spring damping
  double node_damping_Ns_per_m = 3.0;      // D = 3 N·s/m per node (Table 1)
  double areal_density_kg_per_m2 = 0.0;    // mu: an interior node weighs mu h^2
  double min_node_mass_kg = 0.0;           // floor for nodes with a sliver of area (counted)
  double anchor_k_N_per_m = 1.0;           // zero-length spring of each node to its rest position
  double prestrain = 0.0;                  // every spring's rest length = drawn length x (1 - prestrain)
  std::uint32_t extra_vertices = 4096;     // room for nodes cuts add
  std::uint32_t extra_triangles = 8192;
  std::uint32_t extra_springs = 16384;
  std::uint32_t max_vertex_triangles = 24;
  std::int32_t max_node_degree = 32;
  std::vector<std::string> extra_parts;    // part names after "skin", "wound" (e.g. a tool)
};

struct SkinMesh {
  SkinDef def;
  int nx = 0, ny = 0;                      // grid nodes along x, y
  MsmModel model;                          // nodes = vertex slots; x0_m = rest positions
  MsmState state;
  MeshTopology topology;                   // parts: 0 "skin", 1 "wound"
  std::vector<std::uint8_t> on_border;     // (vertex capacity) node on the patch border (never a wound)
  std::vector<std::uint8_t> on_lip;        // (vertex capacity) node a cut placed on the incision
  std::vector<std::uint32_t> lip_nodes;    // live lip nodes (capacity: vertex capacity)
  // Wound faces: boundary edges a -> b along the incision, tissue on their
  // left (counter-clockwise, seen from +z); rebuilt by the cutter.
  std::vector<std::array<std::uint32_t, 2>> wound_edges;
  // (3 x vertex capacity) constant force holding each node's pre-stressed
  // springs in balance at its rest position; UpdatePrestressHold keeps it.
  Eigen::Matrix3Xd hold_N;
  std::uint64_t mass_floor_hits = 0;       // nodes lumped below min_node_mass_kg
};

inline constexpr std::uint16_t kSkinPart = 0, kWoundPart = 1;

// Builds the patch (throws std::invalid_argument on a bad def).
SkinMesh BuildSkinMesh(const SkinDef& def);

// Lumps node v's mass from its live triangles' rest areas (floored) and
// updates the model's mass and inverse mass. No allocation.
void RelumpNodeMass(SkinMesh& skin, std::uint32_t v);
double TotalNodeMass_kg(const SkinMesh& skin);
double LiveRestArea_m2(const SkinMesh& skin);  // sum of the live triangles' rest areas

// The isotropic lattice's spring stiffness K for a membrane of Young's
// modulus E and thickness t: E t = 8 K / 3 (and k_b = K / 4, nu = 1/3).
// Independent of the spacing, as for any 2-D lattice.
constexpr double LatticeSpringStiffness_N_per_m(double youngs_modulus_Pa, double thickness_m) {
  return 3.0 * youngs_modulus_Pa * thickness_m / 8.0;
}
// The prestrain that puts the isotropic lattice under a uniform biaxial
// tension sigma (a spring of drawn length L carries K L prestrain; per unit
// thickness the lattice's biaxial stress is 4 K prestrain / t).
constexpr double LatticePrestrainForStress(double stress_Pa, double youngs_modulus_Pa) {
  return 2.0 * stress_Pa / (3.0 * youngs_modulus_Pa);
}

// hold_N = minus the live springs' force on each node at the rest
// positions (x0_m). After any edit of the springs. No allocation.
void UpdatePrestressHold(SkinMesh& skin);
// The same for one node, from its own springs (after a local edit).
void UpdatePrestressHoldOf(SkinMesh& skin, std::uint32_t node);

// Residual stress on the wound (cutting paper eqs. 3-4): each wound edge of
// rest length l0 carries sigma_r t l0 (the face's area times the stress),
// half on each end, in the skin plane perpendicular to the edge as it is
// now, towards the tissue — the wound lips are pulled apart as the cut
// releases the skin's tension. Writes f_residual_N of the
// lip nodes (zeroing the others it wrote before). No allocation.
void ApplyResidualStress(SkinMesh& skin, double sigma_r_Pa, double thickness_m);

}  // namespace hapsim::core
