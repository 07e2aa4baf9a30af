// A session's topology edits as the frame pump has collected them from its
// snapshots: the edits [First(), End()) in order, from which each viewer
// stream is brought from the version it holds to the snapshot's. Kept by
// the ViewerHub per session and used on the frame pump thread only. Bounded
// (the oldest edits are dropped); a stream whose version is no longer
// covered gets a keyframe instead.
#pragma once
#include <cstdint>
#include <vector>

#include "hapsim/core/mesh/topology_log.h"
#include "hapsim/runtime/scene_snapshot.h"

namespace hapsim::service {

class TopologyHistory {
 public:
  explicit TopologyHistory(std::size_t capacity = 1 << 16) : capacity_(capacity) {}

  // Takes the snapshot's edits. If they do not continue the history (the
  // scene's log wrapped or restarted meanwhile), the history restarts at
  // the snapshot's first edit.
  void Absorb(const SceneSnapshot& snapshot);

  std::uint64_t First() const { return first_; }
  std::uint64_t End() const { return end_; }
  // Whether the edits [from, to) are all here.
  bool Covers(std::uint64_t from, std::uint64_t to) const { return started_ && first_ <= from && from <= to && to <= end_; }
  const core::TopologyEdit& At(std::uint64_t version) const { return ring_[version % ring_.size()]; }

 private:
  std::size_t capacity_;
  std::vector<core::TopologyEdit> ring_;  // grown to capacity_ on the first edit (pump thread: may allocate)
  bool started_ = false;
  std::uint64_t first_ = 0, end_ = 0;
};

}  // namespace hapsim::service
