#pragma once
// Storage for refsim's vector loops: arrays that start on a cache line, so that a 64-byte
// AVX-512 load or store at a multiple of eight elements never straddles two lines
// (std::vector's default allocation is only 16-byte aligned: unless an array happens to start
// on a line, every such access to it splits).
#include <cstddef>
#include <new>
#include <vector>

namespace granstack::refsim::detail {

inline constexpr std::size_t kCacheLine = 64;

template <class T>
struct CacheLineAllocator {
  using value_type = T;
  CacheLineAllocator() = default;
  template <class U>
  CacheLineAllocator(const CacheLineAllocator<U>&) noexcept {}
  T* allocate(std::size_t n) { return static_cast<T*>(::operator new(n * sizeof(T), std::align_val_t{kCacheLine})); }
  void deallocate(T* p, std::size_t) noexcept { ::operator delete(p, std::align_val_t{kCacheLine}); }
  template <class U>
  bool operator==(const CacheLineAllocator<U>&) const noexcept {
    return true;
  }
};

template <class T>
using AlignedVector = std::vector<T, CacheLineAllocator<T>>;

}  // namespace granstack::refsim::detail
