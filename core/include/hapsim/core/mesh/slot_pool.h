// Stable slots with a free list and generation counts, after Box2D v3's
// b2IdPool: an element keeps its slot index for life, removing one never
// renumbers the others, and a freed slot is reused (last freed, first
// reused — deterministic). A SlotHandle (index + generation) held elsewhere
// can tell whether its element is still the one in the slot.
//
// Capacity is fixed at construction; Alloc() and Free() never allocate and
// never throw (a full pool answers kNoSlot; freeing a free slot is a
// programming error, HAPSIM_DEMAND).
#pragma once
#include <cstdint>
#include <vector>

namespace hapsim::core {

inline constexpr std::uint32_t kNoSlot = 0xffffffffu;

struct SlotHandle {
  std::uint32_t index = kNoSlot;
  std::uint32_t generation = 0;
  friend bool operator==(const SlotHandle&, const SlotHandle&) = default;
};

class SlotPool {
 public:
  explicit SlotPool(std::uint32_t capacity = 0);

  // A free slot (the most recently freed one, else the next never used), or
  // kNoSlot when all `capacity` slots are live.
  std::uint32_t Alloc();
  void Free(std::uint32_t slot);

  bool IsLive(std::uint32_t slot) const { return slot < high_water_ && live_[slot] != 0; }
  // Bumped every time the slot is freed: a handle from before is stale.
  std::uint32_t Generation(std::uint32_t slot) const { return generation_[slot]; }
  SlotHandle Handle(std::uint32_t slot) const { return {slot, generation_[slot]}; }
  bool IsValid(const SlotHandle& h) const { return IsLive(h.index) && generation_[h.index] == h.generation; }

  std::uint32_t Capacity() const { return static_cast<std::uint32_t>(live_.size()); }
  // Slots ever handed out: every live slot is below this.
  std::uint32_t HighWater() const { return high_water_; }
  std::uint32_t LiveCount() const { return live_count_; }
  const std::vector<std::uint8_t>& LiveFlags() const { return live_; }  // (capacity) 1 = live

  // Back to a copy of `other`'s state (same capacity; no allocation).
  void CopyFrom(const SlotPool& other);

 private:
  std::vector<std::uint8_t> live_;          // (capacity)
  std::vector<std::uint32_t> generation_;   // (capacity)
  std::vector<std::uint32_t> free_;         // freed slots below high_water_, reserved to capacity
  std::uint32_t high_water_ = 0;
  std::uint32_t live_count_ = 0;
};

}  // namespace hapsim::core
