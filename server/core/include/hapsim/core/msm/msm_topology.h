// Topology edits cutting needs, made between steps (never inside one).
//
// Springs are removed by swap-remove: the last spring moves into the freed
// slot, so the hot loop stays dense and branch-free (no "active" mask to
// test per spring). Consequence: spring indices are not stable across a
// RemoveSpring — callers that track springs must look them up by endpoints
// (FindSpring). Adding writes into capacity reserved at build: O(1), no
// reallocation, so a workspace sized from the model stays valid.
#pragma once
#include <cstdint>

#include <Eigen/Core>

#include "hapsim/core/msm/msm_model.h"
#include "hapsim/core/msm/msm_state.h"

namespace hapsim::core {

// Index of the spring joining a and b (either order), or -1. O(springs).
std::int32_t FindSpring(const MsmModel& model, std::int32_t a, std::int32_t b);

// Removes spring s (swap-remove). Throws std::out_of_range for a bad index.
void RemoveSpring(MsmModel& model, std::int32_t s);

// Appends a spring; returns its index. Throws std::invalid_argument for bad
// nodes/coefficients and std::length_error when spring_capacity is reached.
std::int32_t AddSpring(MsmModel& model, std::int32_t i, std::int32_t j, double rest_m,
                       double k_N_per_m, double c_Ns_per_m);

// Sets the residual-stress force on one node [N] (cut wound edges retract).
void SetResidualForce(MsmState& state, std::int32_t node, const Eigen::Vector3d& f_N);

}  // namespace hapsim::core
