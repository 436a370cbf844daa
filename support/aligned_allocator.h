// A std::allocator that aligns to `Align` bytes (64: a cache line, and an AVX-512 register). For buffers that
// the kernels of support/simd.h read with aligned vector loads: Eigen's aligned_allocator aligns only to what
// the baseline build's Eigen needs (16 bytes), less than an AVX register.
#pragma once

#include <cstddef>
#include <new>

namespace cshapes {

template <class T, std::size_t Align = 64>
struct AlignedAllocator {
  using value_type = T;
  template <class U>
  struct rebind {
    using other = AlignedAllocator<U, Align>;
  };
  AlignedAllocator() = default;
  template <class U>
  AlignedAllocator(const AlignedAllocator<U, Align>&) {}
  T* allocate(std::size_t n) {
    return static_cast<T*>(::operator new(n * sizeof(T), std::align_val_t(Align)));
  }
  void deallocate(T* p, std::size_t) { ::operator delete(p, std::align_val_t(Align)); }
  template <class U>
  bool operator==(const AlignedAllocator<U, Align>&) const {
    return true;
  }
  template <class U>
  bool operator!=(const AlignedAllocator<U, Align>&) const {
    return false;
  }
};

}  // namespace cshapes
