// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// A std::vector whose resize() leaves trivially-constructible elements uninitialised.
// Large CSR arrays (neighbour indices, distances, volumes) are sized once and then
// filled in parallel; zero-filling them first cost a third of the neighbour-search time.
// Arrays of 4 MiB or more are also 2 MiB-aligned and advised as transparent huge pages
// (Linux): the first touch then costs one page fault per 2 MiB instead of per 4 KiB.
#include <cstdint>
#include <cstdlib>
#include <memory>
#include <new>
#include <type_traits>
#include <vector>
#if defined(__linux__)
#include <sys/mman.h>
#endif

namespace vrsph {

namespace detail {
inline constexpr std::size_t huge_page = std::size_t{2} << 20;       // a transparent huge page
inline constexpr std::size_t huge_threshold = std::size_t{4} << 20;  // arrays worth advising
// Advises the whole 2 MiB pages inside [p, p + bytes) as transparent huge pages (advisory:
// failure only means small pages).
inline void advise_huge_pages([[maybe_unused]] void* p, [[maybe_unused]] std::size_t bytes) {
#if defined(__linux__) && defined(MADV_HUGEPAGE)
  const auto begin = reinterpret_cast<std::uintptr_t>(p);
  const std::uintptr_t first = (begin + huge_page - 1) / huge_page * huge_page, last = (begin + bytes) / huge_page * huge_page;
  if (last > first) ::madvise(reinterpret_cast<void*>(first), last - first, MADV_HUGEPAGE);
#endif
}
}  // namespace detail

template <class T>
class DefaultInitAllocator {
 public:
  using value_type = T;
  DefaultInitAllocator() noexcept = default;
  template <class U>
  DefaultInitAllocator(const DefaultInitAllocator<U>&) noexcept {}

  T* allocate(std::size_t n) {
    const std::size_t bytes = n * sizeof(T);
    if (bytes >= detail::huge_threshold) {
      const std::size_t rounded = (bytes + detail::huge_page - 1) / detail::huge_page * detail::huge_page;
      void* p = std::aligned_alloc(detail::huge_page, rounded);
      if (!p) throw std::bad_alloc();
      detail::advise_huge_pages(p, rounded);
      return static_cast<T*>(p);
    }
    return std::allocator<T>{}.allocate(n);
  }
  void deallocate(T* p, std::size_t n) noexcept {
    if (n * sizeof(T) >= detail::huge_threshold)
      std::free(p);
    else
      std::allocator<T>{}.deallocate(p, n);
  }
  template <class U>
  void construct(U* p) noexcept(std::is_nothrow_default_constructible_v<U>) {
    ::new (static_cast<void*>(p)) U;  // default-init: no zeroing for trivial types
  }
  template <class U, class... Args>
  void construct(U* p, Args&&... args) {
    ::new (static_cast<void*>(p)) U(std::forward<Args>(args)...);
  }
  template <class U>
  bool operator==(const DefaultInitAllocator<U>&) const noexcept {
    return true;
  }
};

template <class T>
using UninitVector = std::vector<T, DefaultInitAllocator<T>>;

/// Reserves room for n elements in a vector whose contents the caller then overwrites whole
/// (assign(), or resize() and a write of every entry): a buffer that must grow is released
/// first, not copied, and gets 1/16 of headroom, so that an array a moving cloud re-sizes every
/// step by a few entries is not re-allocated (and faulted in again) each time it grows by them.
/// For a plain std::vector (types whose vectors are part of an interface, e.g. Stencil's) of
/// 4 MiB or more, the 2 MiB-aligned part of a new buffer is advised as transparent huge pages
/// before anything touches it (UninitVector's allocator does so itself): the zero-fill of a
/// following assign() or resize() then faults once per 2 MiB instead of per 4 KiB (on the
/// virtual machines we measure on a 4 KiB fault costs microseconds: a 10^6-particle stencil
/// pattern took 1.9 s, nearly all of it page faults; a 10^6-particle update step that
/// re-allocated its pattern took 4.3 s, not 1.6).
template <class T, class Allocator>
void reserve_for_overwrite(std::vector<T, Allocator>& v, std::size_t n) {
  if (n <= v.capacity()) return;
  std::vector<T, Allocator>().swap(v);
  v.reserve(n + n / 16);
  if constexpr (std::is_same_v<Allocator, std::allocator<T>>)
    if (n * sizeof(T) >= detail::huge_threshold) detail::advise_huge_pages(v.data(), v.capacity() * sizeof(T));
}

/// Sizes v to n elements whose old contents will all be overwritten (reserve_for_overwrite's
/// growth; within the capacity nothing moves, and the new elements are not zeroed).
template <class T>
void resize_for_overwrite(UninitVector<T>& v, std::size_t n) {
  reserve_for_overwrite(v, n);
  v.resize(n);
}

}  // namespace vrsph
