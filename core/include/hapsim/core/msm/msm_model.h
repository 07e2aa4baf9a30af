// Mass-spring model (MSM): nodes with mass, linear springs between node
// pairs, zero-length anchor springs to fixed world points, node damping,
// gravity. Model = parameters + topology, built once from a plain MsmDef by
// BuildMsmModel(), which validates and throws std::invalid_argument.
//
// Layout: struct-of-arrays. The spring step streams the spring arrays once
// per force evaluation and gathers/scatters node data by index, so every
// spring field is its own contiguous array (no per-spring objects, no
// branches in the hot loop). Nodes and springs are edited only by
// msm_topology.h (cutting), between steps; node and spring capacities are
// reserved at build, so edits never reallocate. Nodes beyond the ones in
// use are dormant (fixed, no springs, no anchor): the step passes over
// them at the cost of a fixed node.
#pragma once
#include <array>
#include <cstdint>
#include <limits>
#include <vector>

#include <Eigen/Core>

namespace hapsim::core {

// What the user fills in. Per-spring arrays that are left empty take the
// default named in their comment.
struct MsmDef {
  Eigen::Matrix3Xd x0_m;                  // initial node positions [m] (3 x n)
  Eigen::VectorXd mass_kg;                // node masses [kg] (n), > 0
  std::vector<std::uint8_t> fixed;        // 1 = node never moves (n), empty = none
  Eigen::VectorXd node_damping_Ns_per_m;  // absolute damping -D v per node (n), empty = 0
  Eigen::Vector3d gravity_m_per_s2 = Eigen::Vector3d::Zero();

  std::vector<std::array<std::int32_t, 2>> springs;  // node index pairs (s)
  std::vector<double> spring_rest_m;                 // (s), empty = length in x0
  std::vector<double> spring_k_N_per_m;              // (s), >= 0
  std::vector<double> spring_c_Ns_per_m;             // along-spring damping (s), empty = 0
  std::int32_t spring_capacity = 0;                  // room for AddSpring(); >= s (0 = s)
  std::int32_t node_capacity = 0;                    // room for ActivateNode(); >= n (0 = n)
  // Springs each node's adjacency list holds (AddSpring fails, counted by
  // the caller, at a node with this many); 0 = the largest degree at build.
  std::int32_t max_node_degree = 0;

  // Zero-length springs from a node to a fixed world point (the "anchored
  // springs" substrate that holds a surface to its rest shape).
  std::vector<std::int32_t> anchor_node;      // (a)
  Eigen::Matrix3Xd anchor_point_W_m;          // (3 x a)
  std::vector<double> anchor_k_N_per_m;       // (a), >= 0
  std::vector<double> anchor_c_Ns_per_m;      // (a), empty = 0

  // Stability guard: a step whose kinetic energy exceeds this is reported as
  // a blow-up (runaway energy). Infinity disables the energy check.
  double max_kinetic_energy_J = std::numeric_limits<double>::infinity();
};

// Sizes: n = num_nodes = the node capacity (live and dormant nodes), s = the
// springs in use, a = the anchors of the build.
struct MsmModel {
  std::int32_t num_nodes = 0;
  std::vector<std::uint8_t> node_live;    // (n) 1 = simulated; 0 = dormant (fixed, no springs)
  Eigen::Matrix3Xd x0_m;                  // initial positions [m] (3 x n)
  Eigen::VectorXd mass_kg;                // (n)
  Eigen::VectorXd inv_mass_free_per_kg;   // 1/m for free nodes, 0 for fixed (n): a = f * this
  std::vector<std::uint8_t> fixed;        // (n)
  Eigen::VectorXd node_damping_Ns_per_m;  // (n)
  Eigen::Vector3d gravity_m_per_s2 = Eigen::Vector3d::Zero();

  // Springs (size s = NumSprings(), capacity reserved at build).
  std::vector<std::int32_t> spring_i, spring_j;  // endpoints (s)
  std::vector<double> spring_rest_m;             // rest length [m] (s)
  std::vector<double> spring_k_N_per_m;          // stiffness (s)
  std::vector<double> spring_c_Ns_per_m;         // damping along the spring (s)
  std::int32_t spring_capacity = 0;

  // Per-node spring adjacency: node i's springs are node_springs[i * max_degree
  // + k] for k < node_degree[i], in the order they were added (build order
  // first). O(degree) lookups and edits; kept up to date by msm_topology.h.
  std::int32_t max_degree = 0;
  std::vector<std::int32_t> node_degree;   // (n)
  std::vector<std::int32_t> node_springs;  // (n x max_degree)

  std::vector<std::int32_t> anchor_node;     // (a)
  Eigen::Matrix3Xd anchor_point_W_m;         // (3 x a)
  std::vector<double> anchor_k_N_per_m;      // (a)
  std::vector<double> anchor_c_Ns_per_m;     // (a)

  double max_kinetic_energy_J = std::numeric_limits<double>::infinity();

  // Derived at build so the step folds node damping and every anchor into
  // one pass over the nodes (anchors are zero-length and linear, so they
  // sum): f_i += -absolute_damping_i v_i - anchor_k_sum_i x_i + anchor_kp_sum_i.
  Eigen::VectorXd absolute_damping_Ns_per_m;  // D_i + sum of anchor c at i (n)
  Eigen::VectorXd anchor_k_sum_N_per_m;       // sum of anchor k at i (n)
  Eigen::Matrix3Xd anchor_kp_sum_N;           // sum of k_a p_a at i [N] (3 x n)

  std::int32_t NumSprings() const { return static_cast<std::int32_t>(spring_i.size()); }
  // data() + offset: a model without springs has an empty list (no element to index).
  const std::int32_t* SpringsOf(std::int32_t node) const {
    return node_springs.data() + static_cast<std::size_t>(node) * static_cast<std::size_t>(max_degree);
  }
  std::int32_t DegreeOf(std::int32_t node) const { return node_degree[static_cast<std::size_t>(node)]; }
  std::int32_t NumAnchors() const { return static_cast<std::int32_t>(anchor_node.size()); }
};

// Validates def (sizes, indices in range, no self-springs, positive masses,
// finite non-negative coefficients) and builds the model.
// Throws std::invalid_argument naming the offending field.
MsmModel BuildMsmModel(const MsmDef& def);

}  // namespace hapsim::core
