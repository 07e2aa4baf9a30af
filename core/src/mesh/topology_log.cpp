#include "hapsim/core/mesh/topology_log.h"

namespace hapsim::core {

void TopologyLog::Push(const TopologyEdit& edit) {
  if (ring_.empty()) {  // no history kept: every edit is a restart for viewers
    ++version_;
    oldest_ = version_;
    return;
  }
  ring_[version_ % ring_.size()] = edit;
  ++version_;
  if (version_ - oldest_ > ring_.size()) oldest_ = version_ - ring_.size();
}

void TopologyLog::Restart() {
  ++version_;
  oldest_ = version_;
}

}  // namespace hapsim::core
