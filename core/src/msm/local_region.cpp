#include "hapsim/core/msm/local_region.h"

#include <algorithm>

#include "hapsim/core/assert.h"

namespace hapsim::core {

LocalRegion MakeLocalRegion(const MsmModel& m) {
  const auto n = static_cast<std::size_t>(m.num_nodes);
  const auto cap = static_cast<std::size_t>(m.spring_capacity);
  LocalRegion r;
  r.active_nodes.reserve(n);
  r.touched_nodes.reserve(n);
  r.springs.reserve(cap);
  r.hops.assign(n, -1);
  r.queue.reserve(n);
  r.spring_mark.assign(cap, 0);
  return r;
}

namespace {

// From the BFS marks in r.hops (>= 0 = active), fills the output lists.
void CollectRegion(const MsmModel& m, LocalRegion& r) {
  r.springs.clear();
  r.touched_nodes.clear();
  for (std::int32_t i : r.active_nodes) {
    const std::int32_t* springs = m.SpringsOf(i);
    for (std::int32_t e = 0; e < m.DegreeOf(i); ++e) {
      const auto s = static_cast<std::size_t>(springs[e]);
      if (!r.spring_mark[s]) {
        r.spring_mark[s] = 1;
        r.springs.push_back(static_cast<std::int32_t>(s));
      }
    }
  }
  // Touched = endpoints of region springs plus active nodes; reuse hops as a mark.
  for (std::int32_t i : r.active_nodes) r.hops[static_cast<std::size_t>(i)] = -2;
  for (std::int32_t s : r.springs) {
    r.hops[static_cast<std::size_t>(m.spring_i[static_cast<std::size_t>(s)])] = -2;
    r.hops[static_cast<std::size_t>(m.spring_j[static_cast<std::size_t>(s)])] = -2;
  }
  for (std::int32_t i = 0; i < m.num_nodes; ++i) {
    if (r.hops[static_cast<std::size_t>(i)] == -2) {
      r.touched_nodes.push_back(i);
      r.hops[static_cast<std::size_t>(i)] = -1;
    }
  }
  for (std::int32_t s : r.springs) r.spring_mark[static_cast<std::size_t>(s)] = 0;
  std::sort(r.springs.begin(), r.springs.end());
}

}  // namespace

void SelectLocalRegion(const MsmModel& m, std::int32_t seed, std::int32_t max_hops, LocalRegion& r) {
  // Reachable from a scene's Step(): a programming error, not bad input.
  HAPSIM_DEMAND(seed >= 0 && seed < m.num_nodes, "SelectLocalRegion: seed node out of [0, num_nodes)");
  // BFS over spring adjacency up to max_hops.
  r.queue.clear();
  r.queue.push_back(seed);
  r.hops[static_cast<std::size_t>(seed)] = 0;
  for (std::size_t head = 0; head < r.queue.size(); ++head) {
    const std::int32_t i = r.queue[head];
    const std::int32_t h = r.hops[static_cast<std::size_t>(i)];
    if (h >= max_hops) continue;
    const std::int32_t* springs = m.SpringsOf(i);
    for (std::int32_t e = 0; e < m.DegreeOf(i); ++e) {
      const auto s = static_cast<std::size_t>(springs[e]);
      const auto j = static_cast<std::size_t>(m.spring_i[s] == i ? m.spring_j[s] : m.spring_i[s]);
      if (r.hops[j] < 0) {
        r.hops[j] = h + 1;
        r.queue.push_back(static_cast<std::int32_t>(j));
      }
    }
  }
  r.active_nodes.clear();
  for (std::int32_t i : r.queue) {
    r.hops[static_cast<std::size_t>(i)] = -1;
    if (!m.fixed[static_cast<std::size_t>(i)]) r.active_nodes.push_back(i);
  }
  std::sort(r.active_nodes.begin(), r.active_nodes.end());
  CollectRegion(m, r);
}

void SelectAllNodes(const MsmModel& m, LocalRegion& r) {
  r.active_nodes.clear();
  for (std::int32_t i = 0; i < m.num_nodes; ++i)
    if (!m.fixed[static_cast<std::size_t>(i)]) r.active_nodes.push_back(i);  // dormant nodes are fixed
  CollectRegion(m, r);
}

}  // namespace hapsim::core
