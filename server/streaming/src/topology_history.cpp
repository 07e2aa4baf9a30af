#include "hapsim/streaming/topology_history.h"

#include <algorithm>

namespace hapsim::service {

void TopologyHistory::Absorb(const SceneSnapshot& s) {
  if (!started_ || s.edits_from_version > end_ || s.topology_version < end_) {
    started_ = true;
    first_ = end_ = s.edits_from_version;
  }
  for (std::size_t k = 0; k < s.topology_edits.size(); ++k) {
    const std::uint64_t v = s.edits_from_version + k;
    if (v < end_) continue;  // already taken from an earlier snapshot
    if (ring_.empty()) ring_.resize(std::max<std::size_t>(capacity_, 1));
    ring_[v % ring_.size()] = s.topology_edits[k];
    end_ = v + 1;
    if (end_ - first_ > ring_.size()) first_ = end_ - ring_.size();
  }
  // A restart without edits (a reset): nothing before the snapshot's version
  // can be replayed.
  if (end_ < s.topology_version) first_ = end_ = s.topology_version;
}

}  // namespace hapsim::service
