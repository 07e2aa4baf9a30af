// Single-producer / single-consumer "latest value" mailbox (a triple buffer).
// The real-time paths (1 kHz bridge servo, session tick) hand data to and from
// I/O threads through these: both sides are wait-free, nothing blocks, the
// consumer always gets the newest value and older ones are simply overwritten
// (newest state wins). Each slot is owned by exactly one side at a time, so
// there is no data race on T.
#pragma once
#include <array>
#include <atomic>

namespace hapsim::common {

template <class T>
class LatestValue {
 public:
  // Producer side (one thread only).
  void Publish(const T& value) {
    slots_[back_] = value;
    const unsigned previous = middle_.exchange(back_ | kFresh, std::memory_order_acq_rel);
    back_ = previous & kIndexMask;
  }

  // Consumer side (one thread only): copies the newest value into *out if one
  // was published since the last successful take; returns whether it did.
  bool TakeIfNew(T* out) {
    if ((middle_.load(std::memory_order_acquire) & kFresh) == 0) return false;
    const unsigned previous = middle_.exchange(front_, std::memory_order_acq_rel);
    front_ = previous & kIndexMask;
    *out = slots_[front_];
    return true;
  }

 private:
  static constexpr unsigned kFresh = 4;
  static constexpr unsigned kIndexMask = 3;
  std::array<T, 3> slots_{};
  unsigned back_ = 0;    // producer's slot
  unsigned front_ = 1;   // consumer's slot
  std::atomic<unsigned> middle_{2};  // the shared slot, plus the kFresh bit
};

}  // namespace hapsim::common
