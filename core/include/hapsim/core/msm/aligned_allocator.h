// A std::allocator that aligns every block to kAlignBytes (C++17 aligned
// new), for arrays read with full-width vector loads: a 32-byte record in a
// 64-byte-aligned array never straddles two cache lines.
#pragma once
#include <cstddef>
#include <new>

namespace hapsim::core {

template <class T, std::size_t kAlignBytes>
struct AlignedAllocator {
  using value_type = T;
  template <class U>
  struct rebind {
    using other = AlignedAllocator<U, kAlignBytes>;
  };

  AlignedAllocator() = default;
  template <class U>
  AlignedAllocator(const AlignedAllocator<U, kAlignBytes>&) {}

  T* allocate(std::size_t n) {
    return static_cast<T*>(::operator new(n * sizeof(T), std::align_val_t{kAlignBytes}));
  }
  void deallocate(T* p, std::size_t) { ::operator delete(p, std::align_val_t{kAlignBytes}); }

  template <class U>
  bool operator==(const AlignedAllocator<U, kAlignBytes>&) const { return true; }
  template <class U>
  bool operator!=(const AlignedAllocator<U, kAlignBytes>&) const { return false; }
};

}  // namespace hapsim::core
