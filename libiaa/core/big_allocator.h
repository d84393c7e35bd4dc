// An allocator for large arrays that are filled once and read a few times (the certified mesher's
// leaves, corner table and per-leaf results: millions of elements, hundreds of megabytes).
//
// Why: the first write to each fresh 4 KiB page of memory costs a page fault, and on the virtual
// machines iaa is measured on a fault costs about 6 microseconds. The certified mesh of the thin
// torus (data/scenes/thin_torus.toml) touched 190 MB through 48 000 faults, about 0.3 s of CPU in
// a 1.7 s run. Blocks of 2 MiB and more are therefore mapped on their own, aligned to 2 MiB and
// marked for transparent huge pages (madvise MADV_HUGEPAGE, which the Linux default setting
// `madvise` honours): one fault then brings in 2 MiB. Smaller blocks come from operator new.
// Elsewhere than on Linux, every block comes from operator new.
#pragma once

#include <cstddef>
#include <cstdint>
#include <new>
#include <vector>

#if defined(__linux__)
#include <sys/mman.h>
#endif

namespace iaa {

namespace detail {

inline constexpr std::size_t kHugePage = std::size_t{2} << 20;

/// `bytes` rounded up to whole huge pages.
inline std::size_t huge_size(std::size_t bytes) {
  return (bytes + kHugePage - 1) / kHugePage * kHugePage;
}

/// A mapping of huge_size(bytes) bytes at a 2 MiB boundary, advised to use huge pages; null when
/// the system refuses.
inline void* map_huge(std::size_t bytes) {
#if defined(__linux__)
  const std::size_t size = huge_size(bytes);
  // Map one huge page more and trim both ends, so that what remains starts at a boundary.
  void* raw =
      ::mmap(nullptr, size + kHugePage, PROT_READ | PROT_WRITE, MAP_PRIVATE | MAP_ANONYMOUS, -1, 0);
  if (raw == MAP_FAILED) return nullptr;
  const auto start = reinterpret_cast<std::uintptr_t>(raw);
  const std::uintptr_t aligned = (start + kHugePage - 1) / kHugePage * kHugePage;
  if (aligned > start) ::munmap(raw, aligned - start);
  const std::uintptr_t end = start + size + kHugePage;
  if (end > aligned + size) ::munmap(reinterpret_cast<void*>(aligned + size), end - aligned - size);
  void* p = reinterpret_cast<void*>(aligned);
  ::madvise(p, size, MADV_HUGEPAGE);  // advice only: without it the mapping still works
  return p;
#else
  (void)bytes;
  return nullptr;
#endif
}

inline void unmap_huge(void* p, std::size_t bytes) {
#if defined(__linux__)
  ::munmap(p, huge_size(bytes));
#else
  (void)p, (void)bytes;
#endif
}

}  // namespace detail

/// std::allocator's interface; on Linux, blocks of 2 MiB and more come from map_huge.
template <class T>
struct BigAllocator {
  using value_type = T;

  BigAllocator() = default;
  template <class U>
  BigAllocator(const BigAllocator<U>&) noexcept {}  // NOLINT: converting, as std::allocator

  T* allocate(std::size_t n) {
    if (n > static_cast<std::size_t>(-1) / sizeof(T)) throw std::bad_array_new_length();
    const std::size_t bytes = n * sizeof(T);
#if defined(__linux__)
    // Large blocks are always mapped (deallocate tells the two kinds apart by size alone).
    if (bytes >= detail::kHugePage) {
      if (void* p = detail::map_huge(bytes)) return static_cast<T*>(p);
      throw std::bad_alloc();
    }
#endif
    return static_cast<T*>(::operator new (bytes, std::align_val_t{alignof(T)}));
  }

  void deallocate(T* p, std::size_t n) noexcept {
    const std::size_t bytes = n * sizeof(T);
#if defined(__linux__)
    if (bytes >= detail::kHugePage) return detail::unmap_huge(p, bytes);
#endif
    ::operator delete (p, std::align_val_t{alignof(T)});
  }

  template <class U>
  bool operator==(const BigAllocator<U>&) const noexcept {
    return true;
  }
  template <class U>
  bool operator!=(const BigAllocator<U>&) const noexcept {
    return false;
  }
};

/// A vector whose large buffers use huge pages (see BigAllocator).
template <class T>
using BigVector = std::vector<T, BigAllocator<T>>;

}  // namespace iaa
