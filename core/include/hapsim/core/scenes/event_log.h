// Bounded, allocation-free event log for scenes: capacity is reserved once;
// when full, the oldest event is dropped (shifted out) so Events() stays one
// contiguous span, oldest first.
#pragma once
#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

#include "hapsim/core/scenes/scene.h"

namespace hapsim::core {

class EventLog {
 public:
  explicit EventLog(std::size_t capacity = 256) { events_.reserve(capacity); capacity_ = capacity; }
  void Push(const SceneEvent& e) {
    if (capacity_ == 0) return;
    if (events_.size() == capacity_) events_.erase(events_.begin());  // no realloc: size shrinks
    events_.push_back(e);                                             // within reserved capacity
    ++total_;
  }
  void Clear() { events_.clear(); }
  std::span<const SceneEvent> View() const { return events_; }
  std::uint64_t TotalPushed() const { return total_; }

 private:
  std::vector<SceneEvent> events_;
  std::size_t capacity_ = 0;
  std::uint64_t total_ = 0;
};

}  // namespace hapsim::core
