// Replaced global operator new/delete that count allocations while the
// calling thread's flag is set (see allocation_counter.h).
#include "allocation_counter.h"

#include <cstdlib>
#include <new>

namespace hapsim::test {
std::uint64_t& ThreadAllocationCount() {
  thread_local std::uint64_t count = 0;
  return count;
}
bool& ThreadAllocationCounting() {
  thread_local bool counting = false;
  return counting;
}
}  // namespace hapsim::test

namespace {
void* CountedAlloc(std::size_t size) {
  if (hapsim::test::ThreadAllocationCounting()) ++hapsim::test::ThreadAllocationCount();
  if (void* p = std::malloc(size == 0 ? 1 : size)) return p;
  throw std::bad_alloc();
}
void* CountedAlignedAlloc(std::size_t size, std::align_val_t align) {
  if (hapsim::test::ThreadAllocationCounting()) ++hapsim::test::ThreadAllocationCount();
  const auto a = static_cast<std::size_t>(align);
  if (void* p = std::aligned_alloc(a, (size + a - 1) / a * a)) return p;
  throw std::bad_alloc();
}
}  // namespace

void* operator new(std::size_t size) { return CountedAlloc(size); }
void* operator new[](std::size_t size) { return CountedAlloc(size); }
void* operator new(std::size_t size, std::align_val_t a) { return CountedAlignedAlloc(size, a); }
void* operator new[](std::size_t size, std::align_val_t a) { return CountedAlignedAlloc(size, a); }
void operator delete(void* p) noexcept { std::free(p); }
void operator delete[](void* p) noexcept { std::free(p); }
void operator delete(void* p, std::size_t) noexcept { std::free(p); }
void operator delete[](void* p, std::size_t) noexcept { std::free(p); }
void operator delete(void* p, std::align_val_t) noexcept { std::free(p); }
void operator delete[](void* p, std::align_val_t) noexcept { std::free(p); }
void operator delete(void* p, std::size_t, std::align_val_t) noexcept { std::free(p); }
void operator delete[](void* p, std::size_t, std::align_val_t) noexcept { std::free(p); }
