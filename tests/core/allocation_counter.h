// Counts heap allocations made by this thread while a ScopedAllocationCount
// is alive. The global operator new replacement lives in
// allocation_counter.cpp — ONE per test binary, so every test in
// hapsim-core-tests that needs "allocates nothing" should use this header
// instead of replacing operator new again.
#pragma once
#include <cstdint>

namespace hapsim::test {

std::uint64_t& ThreadAllocationCount();
bool& ThreadAllocationCounting();

class ScopedAllocationCount {
 public:
  ScopedAllocationCount() {
    ThreadAllocationCount() = 0;
    ThreadAllocationCounting() = true;
  }
  ~ScopedAllocationCount() { ThreadAllocationCounting() = false; }
  std::uint64_t Count() const { return ThreadAllocationCount(); }
  ScopedAllocationCount(const ScopedAllocationCount&) = delete;
  ScopedAllocationCount& operator=(const ScopedAllocationCount&) = delete;
};

}  // namespace hapsim::test
