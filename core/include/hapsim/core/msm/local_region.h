// Local update region (gingival paper, section 1): far from the contact the
// tissue barely moves, so only nodes within a graph distance of the contact
// are integrated and the rest are frozen. The region is rebuilt between
// steps (e.g. when the contact node changes, or after a cut) without
// allocating: it walks the model's own per-node spring adjacency, which
// topology edits keep current. Anchors need no list: the step applies them
// per node (MsmModel anchor sums).
#pragma once
#include <cstdint>
#include <vector>

#include "hapsim/core/msm/msm_model.h"

namespace hapsim::core {

struct LocalRegion {
  // Output of SelectLocalRegion, sorted ascending (deterministic order):
  std::vector<std::int32_t> active_nodes;     // integrated (free nodes only)
  std::vector<std::int32_t> springs;          // springs with >= 1 active end
  std::vector<std::int32_t> touched_nodes;    // active nodes + their spring neighbours

  // BFS scratch.
  std::vector<std::int32_t> hops;             // (n), -1 = not reached
  std::vector<std::int32_t> queue;            // (n)
  std::vector<std::uint8_t> spring_mark;      // (capacity)
};

// Reserves every buffer for the model's node and spring capacities (allocates).
LocalRegion MakeLocalRegion(const MsmModel& model);

// Selects the free nodes within `max_hops` spring hops of `seed_node`. Never
// allocates, never throws: a seed outside [0, num_nodes) is a programming
// error (HAPSIM_DEMAND aborts with a message).
void SelectLocalRegion(const MsmModel& model, std::int32_t seed_node, std::int32_t max_hops,
                       LocalRegion& region);

// Every free live node active (equivalent to a full update; for comparisons).
void SelectAllNodes(const MsmModel& model, LocalRegion& region);

}  // namespace hapsim::core
