// The arena and its allocator (core/arena.h): pieces aligned and apart, blocks for large
// requests, and containers that take their arena along when moved or swapped, so that memory is
// never given back through the wrong allocator (the sanitizer build checks the frees), and copies
// that leave it alone.
#include "core/arena.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cstdint>
#include <utility>
#include <vector>

namespace iaa {
namespace {

TEST(Arena, PiecesAreAlignedAndDoNotOverlap) {
  Arena arena;
  std::vector<std::pair<std::uintptr_t, std::size_t>> pieces;  // start, size
  for (std::size_t i = 1; i < 4000; ++i) {
    const std::size_t align = std::size_t{1} << (i % 5);  // 1 .. 16
    const std::size_t size = i % 97 + 1;
    auto* p = static_cast<std::byte*>(arena.take(size, align));
    EXPECT_EQ(reinterpret_cast<std::uintptr_t>(p) % align, 0u);
    p[0] = std::byte{1};  // writable (the sanitizers check the bounds)
    p[size - 1] = std::byte{2};
    pieces.emplace_back(reinterpret_cast<std::uintptr_t>(p), size);
  }
  std::sort(pieces.begin(), pieces.end());
  for (std::size_t i = 1; i < pieces.size(); ++i) {
    EXPECT_LE(pieces[i - 1].first + pieces[i - 1].second, pieces[i].first);
  }
  EXPECT_GE(arena.capacity(), Arena::kBlockBytes);
}

TEST(Arena, LargeRequestsGetABlockOfTheirOwn) {
  Arena arena;
  const std::size_t big = 3 * Arena::kBlockBytes;
  auto* p = static_cast<std::byte*>(arena.take(big, 8));
  p[0] = std::byte{1};
  p[big - 1] = std::byte{1};
  EXPECT_EQ(arena.capacity(), big);
  arena.take(16, 8);  // does not fit the rest of the large block: a new one
  EXPECT_EQ(arena.capacity(), big + Arena::kBlockBytes);
}

TEST(ArenaAllocator, VectorsGrowInTheArenaAndTakeItAlongWhenMoved) {
  Arena arena;
  ArenaVector<std::array<std::uint32_t, 3>> a{ArenaAllocator<std::array<std::uint32_t, 3>>(&arena)};
  for (std::uint32_t i = 0; i < 1000; ++i) a.push_back({i, i + 1, i + 2});
  EXPECT_EQ(a.get_allocator().arena, &arena);
  ArenaVector<std::array<std::uint32_t, 3>> b;  // operator new
  b.push_back({7, 8, 9});
  b = std::move(a);  // takes the arena along with the memory
  EXPECT_EQ(b.get_allocator().arena, &arena);
  ASSERT_EQ(b.size(), 1000u);
  EXPECT_EQ(b[999][2], 1001u);
  ArenaVector<std::array<std::uint32_t, 3>> c;
  c.push_back({1, 2, 3});
  std::swap(b, c);  // each keeps its memory's allocator
  EXPECT_EQ(c.get_allocator().arena, &arena);
  EXPECT_EQ(b.get_allocator().arena, nullptr);
  EXPECT_EQ(b[0][0], 1u);
  EXPECT_EQ(c[0][1], 1u);
  // Copies never take from the arena (another thread may make them).
  const ArenaVector<std::array<std::uint32_t, 3>> copied(c);
  EXPECT_EQ(copied.get_allocator().arena, nullptr);
  EXPECT_EQ(copied[999][2], 1001u);
  b = c;
  EXPECT_EQ(b.get_allocator().arena, nullptr);
  EXPECT_EQ(b.size(), 1000u);
}

}  // namespace
}  // namespace iaa
