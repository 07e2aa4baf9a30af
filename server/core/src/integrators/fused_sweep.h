// Internal: the fused sweep of the one-evaluation explicit schemes (see
// MsmWorkspace::fused_sweep). A step is otherwise two passes over memory —
// all springs, then all nodes — and on meshes larger than the L2 cache the
// node pass reads x, v and f back from L3 or DRAM. Here the node pass
// follows the spring pass chunk by chunk, a few grid rows behind it.
//
// Why it is exact: node i is integrated only once every spring that touches
// it has scattered its force (so f_i is complete) and no later spring reads
// x_i or v_i. Springs and nodes are visited in the same order as the
// two-pass step, so every sum is formed in the same order: bit-identical.
// Which nodes are ready after a chunk comes from each node's last spring:
// node k is ready once springs up to max over j <= k of last_spring[j] are
// done (a prefix maximum, so readiness is a growing prefix of the nodes).
// On a mesh whose springs are not ordered by node the prefix reaches the
// end late and the sweep degrades gracefully into the two-pass step.
#pragma once
#include <algorithm>
#include <cstdint>

#include "step_common.h"

namespace hapsim::core::detail {

// Recomputes ws.fused_node_end for the model's current springs. O(springs +
// nodes), no allocation (the arrays are sized by MakeMsmWorkspace).
inline void RebuildFusedSchedule(const MsmModel& m, MsmWorkspace& ws) {
  std::int32_t* last = ws.node_last_spring.data();
  std::fill(last, last + m.num_nodes, -1);
  const std::int32_t num_springs = m.NumSprings();
  for (std::int32_t s = 0; s < num_springs; ++s) {  // increasing s: ends at the max
    last[m.spring_i[static_cast<std::size_t>(s)]] = s;
    last[m.spring_j[static_cast<std::size_t>(s)]] = s;
  }
  std::int32_t node = 0, prefix_last = -1;
  for (std::int32_t c = 0; c * kFusedChunkSprings < num_springs; ++c) {
    const std::int32_t chunk_end = std::min(num_springs, (c + 1) * kFusedChunkSprings);
    while (node < m.num_nodes && std::max(prefix_last, last[node]) < chunk_end) {
      prefix_last = std::max(prefix_last, last[node]);
      ++node;
    }
    ws.fused_node_end[static_cast<std::size_t>(c)] = node;
  }
  ws.fused_revision = m.topology_revision;
  ws.fused_num_springs = num_springs;
}

// One force evaluation at (x, v) over every spring, and node_pass(ranges)
// over every node, fused chunk by chunk when ws.fused_sweep is set. Full
// update only (the local update's lists are not ordered for it).
template <class NodePass>
void SpringsThenNodes(const MsmModel& m, MsmWorkspace& ws, const double* x, const double* v, double* f,
                      NodePass node_pass) {
  using Dense = Ranges<DenseRange, DenseRange, false>;
  if (!ws.fused_sweep) {
    const DenseRange nodes{m.num_nodes};
    SpringPass(m, ws, x, v, f, Dense{nodes, nodes, DenseRange{m.NumSprings()}});
    node_pass(Dense{nodes, nodes, DenseRange{0}});
    return;
  }
  if (ws.fused_num_springs != m.NumSprings() || ws.fused_revision != m.topology_revision)
    RebuildFusedSchedule(m, ws);
  const std::int32_t num_springs = m.NumSprings();
  std::int32_t node_begin = 0;
  for (std::int32_t c = 0, s0 = 0; s0 < num_springs; ++c, s0 += kFusedChunkSprings) {
    const DenseRange springs{std::min(kFusedChunkSprings, num_springs - s0), s0};
    SpringForces(m, ws.spring_kernel, x, v, f, springs);
    const std::int32_t node_end = ws.fused_node_end[static_cast<std::size_t>(c)];
    if (node_end > node_begin) {
      const DenseRange ready{node_end - node_begin, node_begin};
      node_pass(Dense{ready, ready, DenseRange{0}});
      node_begin = node_end;
    }
  }
  if (node_begin < m.num_nodes) {
    const DenseRange rest{m.num_nodes - node_begin, node_begin};
    node_pass(Dense{rest, rest, DenseRange{0}});
  }
}

}  // namespace hapsim::core::detail
