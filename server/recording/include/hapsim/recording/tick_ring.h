// A bounded single-producer single-consumer queue of TickRecords: the tick
// worker pushes (wait-free, never allocates, refuses when full), the
// recording writer drains. Capacity is fixed at construction.
#pragma once
#include <atomic>
#include <cstddef>
#include <vector>

#include "hapsim/recording/recording_format.h"

namespace hapsim::service {

class TickRing {
 public:
  explicit TickRing(std::size_t capacity) : slots_(capacity + 1) {}

  // Producer (the tick worker). false: full, nothing stored.
  bool Push(const TickRecord& record) {
    const std::size_t head = head_.load(std::memory_order_relaxed);
    const std::size_t next = head + 1 == slots_.size() ? 0 : head + 1;
    if (next == tail_.load(std::memory_order_acquire)) return false;
    slots_[head] = record;
    head_.store(next, std::memory_order_release);
    return true;
  }

  // Consumer (the writer). Appends everything queued to *out; returns how many.
  std::size_t Drain(std::vector<TickRecord>* out) {
    std::size_t tail = tail_.load(std::memory_order_relaxed);
    const std::size_t head = head_.load(std::memory_order_acquire);
    std::size_t n = 0;
    while (tail != head) {
      out->push_back(slots_[tail]);
      tail = tail + 1 == slots_.size() ? 0 : tail + 1;
      ++n;
    }
    tail_.store(tail, std::memory_order_release);
    return n;
  }

  std::size_t capacity() const { return slots_.size() - 1; }

 private:
  std::vector<TickRecord> slots_;
  alignas(64) std::atomic<std::size_t> head_{0};  // next slot the producer writes
  alignas(64) std::atomic<std::size_t> tail_{0};  // next slot the consumer reads
};

}  // namespace hapsim::service
