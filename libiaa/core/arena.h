// A bump allocator for many small arrays that are made by one thread and die together (the
// certified mesher's per-leaf crossings, fan centres and triangles: hundreds of thousands of
// arrays of a few elements each).
//
// Why: each such array from operator new costs a malloc while it is made and a free when the
// whole set goes, and the frees ran on one thread after the mesh was done (13-20 ms of a 0.5 s
// mesh of the thin torus). An arena hands out pieces of large blocks and frees the blocks at
// once; an array that grows leaves its old piece unused until then.
#pragma once

#include <algorithm>
#include <cstddef>
#include <memory>
#include <new>
#include <type_traits>
#include <vector>

namespace iaa {

/// Pieces of blocks of at least kBlockBytes, given out in order and freed with the arena. Not
/// thread-safe: one thread takes from an arena at a time.
class Arena {
 public:
  static constexpr std::size_t kBlockBytes = std::size_t{64} << 10;
  /// operator new's alignment, which every block has and no piece needs more than.
  static constexpr std::size_t kMaxAlign = __STDCPP_DEFAULT_NEW_ALIGNMENT__;

  Arena() = default;
  Arena(const Arena&) = delete;
  Arena& operator=(const Arena&) = delete;

  /// `bytes` bytes aligned to `align` (a power of two, at most kMaxAlign).
  void* take(std::size_t bytes, std::size_t align) {
    std::size_t at = (used_ + align - 1) & ~(align - 1);
    if (blocks_.empty() || at + bytes > size_) {
      size_ = std::max(kBlockBytes, bytes);
      // Default-initialized: the arrays write what they hold.
      blocks_.emplace_back(new std::byte[size_]);
      capacity_ += size_;
      at = 0;
    }
    used_ = at + bytes;
    return blocks_.back().get() + at;
  }
  /// Bytes in the blocks taken so far.
  std::size_t capacity() const { return capacity_; }

 private:
  std::vector<std::unique_ptr<std::byte[]>> blocks_;
  std::size_t size_ = 0;  ///< of the last block
  std::size_t used_ = 0;  ///< of the last block
  std::size_t capacity_ = 0;
};

/// std::allocator's interface over an arena, or over operator new when it has none (the default).
/// The arena moves with the memory: a container moved or swapped into another takes its arena
/// along, so that what it holds is never freed through another allocator. A copy takes operator
/// new, never the arena: it may be made on another thread than the arena's, which takes from it
/// unsynchronized.
template <class T>
struct ArenaAllocator {
  using value_type = T;
  using propagate_on_container_move_assignment = std::true_type;
  using propagate_on_container_copy_assignment = std::false_type;
  using propagate_on_container_swap = std::true_type;
  using is_always_equal = std::false_type;
  static_assert(alignof(T) <= Arena::kMaxAlign);

  ArenaAllocator() = default;
  explicit ArenaAllocator(Arena* a) noexcept : arena(a) {}
  template <class U>
  ArenaAllocator(const ArenaAllocator<U>& o) noexcept : arena(o.arena) {}  // NOLINT: as std's

  ArenaAllocator select_on_container_copy_construction() const noexcept { return {}; }

  T* allocate(std::size_t n) {
    if (n > static_cast<std::size_t>(-1) / sizeof(T)) throw std::bad_array_new_length();
    if (!arena) return static_cast<T*>(::operator new(n * sizeof(T)));
    return static_cast<T*>(arena->take(n * sizeof(T), alignof(T)));
  }
  /// Memory from an arena goes with the arena.
  void deallocate(T* p, std::size_t n) noexcept {
    (void)n;
    if (!arena) ::operator delete(p);
  }
  template <class U>
  bool operator==(const ArenaAllocator<U>& o) const noexcept {
    return arena == o.arena;
  }
  template <class U>
  bool operator!=(const ArenaAllocator<U>& o) const noexcept {
    return arena != o.arena;
  }

  Arena* arena = nullptr;
};

template <class T>
using ArenaVector = std::vector<T, ArenaAllocator<T>>;

}  // namespace iaa
