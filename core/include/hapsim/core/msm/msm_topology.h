// Topology edits cutting needs, made between steps (never inside one).
// After build, none of them allocates or throws: capacities were reserved by
// BuildMsmModel (MsmDef::spring_capacity, node_capacity, max_node_degree).
// A full capacity is answered with kNoSpring / false, for the caller to
// count and report; an index out of range or a dead node is a programming
// error (HAPSIM_DEMAND aborts with a message).
//
// Springs are removed by swap-remove: the last spring moves into the freed
// slot, so the hot loop stays dense and branch-free (no "active" mask to
// test per spring). Spring indices are therefore not stable across a
// RemoveSpring — look springs up by their nodes (FindSpring, O(degree)
// through the per-node adjacency, which every edit keeps up to date).
#pragma once
#include <cstdint>

#include <Eigen/Core>

#include "hapsim/core/msm/msm_model.h"
#include "hapsim/core/msm/msm_state.h"

namespace hapsim::core {

inline constexpr std::int32_t kNoSpring = -1;

// Index of the spring joining a and b (either order), or kNoSpring. O(degree of a).
std::int32_t FindSpring(const MsmModel& model, std::int32_t a, std::int32_t b);

// Removes spring s (swap-remove; the adjacency follows).
void RemoveSpring(MsmModel& model, std::int32_t s);

// Appends a spring between live nodes i != j with finite coefficients >= 0
// and returns its index, or kNoSpring when spring_capacity is reached or i
// or j already has max_degree springs.
std::int32_t AddSpring(MsmModel& model, std::int32_t i, std::int32_t j, double rest_m, double k_N_per_m,
                       double c_Ns_per_m);

// A node brought into the simulation (cutting adds nodes on the incision).
struct NodeDef {
  Eigen::Vector3d x_W_m = Eigen::Vector3d::Zero();  // position, at rest (v = 0) [m]
  double mass_kg = 1e-3;                            // > 0
  double damping_Ns_per_m = 0.0;                    // absolute drag -D v
  // A zero-length anchor spring to x_W_m (the substrate under a skin); 0: none.
  double anchor_k_N_per_m = 0.0;
  double anchor_c_Ns_per_m = 0.0;
};

// Makes dormant node `node` live with def (no springs yet).
void ActivateNode(MsmModel& model, MsmState& state, std::int32_t node, const NodeDef& def);
// Removes every spring of live node `node` and makes it dormant: fixed,
// at rest, no anchor, no residual or external force.
void DeactivateNode(MsmModel& model, MsmState& state, std::int32_t node);

// Sets the residual-stress force on one node [N] (cut wound edges retract).
void SetResidualForce(MsmState& state, std::int32_t node, const Eigen::Vector3d& f_N);

}  // namespace hapsim::core
