#include "hapsim/core/mesh/slot_pool.h"

#include <algorithm>

#include "hapsim/core/assert.h"

namespace hapsim::core {

SlotPool::SlotPool(std::uint32_t capacity) : live_(capacity, 0), generation_(capacity, 0) { free_.reserve(capacity); }

std::uint32_t SlotPool::Alloc() {
  std::uint32_t slot;
  if (!free_.empty()) {
    slot = free_.back();
    free_.pop_back();
  } else if (high_water_ < Capacity()) {
    slot = high_water_++;
  } else {
    return kNoSlot;
  }
  live_[slot] = 1;
  ++live_count_;
  return slot;
}

void SlotPool::Free(std::uint32_t slot) {
  HAPSIM_DEMAND(IsLive(slot), "SlotPool::Free: the slot is not live");
  live_[slot] = 0;
  ++generation_[slot];
  --live_count_;
  free_.push_back(slot);  // within reserved capacity: no allocation
}

void SlotPool::CopyFrom(const SlotPool& other) {
  HAPSIM_DEMAND(other.Capacity() == Capacity(), "SlotPool::CopyFrom: capacities differ");
  std::copy(other.live_.begin(), other.live_.end(), live_.begin());
  std::copy(other.generation_.begin(), other.generation_.end(), generation_.begin());
  free_.assign(other.free_.begin(), other.free_.end());  // size <= reserved capacity
  high_water_ = other.high_water_;
  live_count_ = other.live_count_;
}

}  // namespace hapsim::core
