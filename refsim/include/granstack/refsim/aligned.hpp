#pragma once
// Storage for refsim's vector loops: arrays that start on a cache line, so that a 64-byte
// AVX-512 load or store at a multiple of eight elements never straddles two lines
// (std::vector's default allocation is only 16-byte aligned: unless an array happens to start
// on a line, every such access to it splits).
#include <algorithm>
#include <cstddef>
#include <new>
#include <type_traits>
#include <utility>
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
  // An element made without a value (resize(n)) is left unwritten where its type allows: the
  // code that makes the array writes it, on the thread that will use it (fill_in_shares).
  template <class U, class... Args>
  void construct(U* p, Args&&... args) {
    if constexpr (sizeof...(Args) == 0 && std::is_trivially_default_constructible_v<U>) {
      ::new (static_cast<void*>(p)) U;
    } else {
      ::new (static_cast<void*>(p)) U(std::forward<Args>(args)...);
    }
  }
  template <class U>
  bool operator==(const CacheLineAllocator<U>&) const noexcept {
    return true;
  }
};

template <class T>
using AlignedVector = std::vector<T, CacheLineAllocator<T>>;

// `v` as `n` copies of `value`, written in `shares`' shares (each of the threads first touching
// the pages it writes, in parallel, where one thread would take every page fault of a large
// array in turn), or in one where `shares` is empty.
template <class T, class Shares>
void fill_in_shares(AlignedVector<T>& v, std::size_t n, T value, const Shares& shares) {
  v.clear();
  v.resize(n);  // unwritten
  const auto fill = [&](std::size_t begin, std::size_t end) {
    std::fill(v.begin() + static_cast<std::ptrdiff_t>(begin), v.begin() + static_cast<std::ptrdiff_t>(end), value);
  };
  if (shares) {
    shares(n, fill);
  } else {
    fill(0, n);
  }
}

}  // namespace granstack::refsim::detail
