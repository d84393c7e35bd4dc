// Sorting by 64-bit keys, for the meshers' millions of grid keys and crossing ids: an LSD radix
// sort, several times faster than a comparison sort at these sizes.
#pragma once

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <utility>
#include <vector>

#include <tbb/parallel_for.h>

#include "core/big_allocator.h"

namespace iaa::detail {

/// LSD radix sort of a[0..n) by key(element), a 64-bit integer, 11 bits per pass; passes whose
/// digit is the same for every key (grid keys leave most of their high bits equal) are skipped.
/// Stable. `tmp` is scratch for n elements.
template <class T, class KeyOf>
void radix_sort_serial(T* a, T* tmp, std::size_t n, KeyOf key) {
  constexpr int kDigit = 11, kPasses = 6;
  constexpr std::size_t kBuckets = std::size_t{1} << kDigit;
  std::vector<std::size_t> count(kPasses * kBuckets, 0);
  for (std::size_t i = 0; i < n; ++i) {
    const std::uint64_t v = key(a[i]);
    for (int p = 0; p < kPasses; ++p)
      ++count[std::size_t(p) * kBuckets + ((v >> (p * kDigit)) & (kBuckets - 1))];
  }
  T* src = a;
  T* dst = tmp;
  for (int p = 0; p < kPasses; ++p) {
    std::size_t* c = &count[std::size_t(p) * kBuckets];
    if (std::any_of(c, c + kBuckets, [&](std::size_t k) { return k == n; })) continue;
    std::size_t sum = 0;
    for (std::size_t b = 0; b < kBuckets; ++b) sum += std::exchange(c[b], sum);
    for (std::size_t i = 0; i < n; ++i)
      dst[c[(key(src[i]) >> (p * kDigit)) & (kBuckets - 1)]++] = src[i];
    std::swap(src, dst);
  }
  if (src != a) std::copy(src, src + n, a);
}

/// Sorts a[0..n) by key, ascending: four parts radix-sorted in parallel (TBB, in the caller's
/// arena), then merged. The parts do not depend on the thread count, so neither does the result:
/// elements with equal keys keep their input order within a part and the merges take the left
/// part's first.
template <class T, class KeyOf>
void radix_sort(T* a, std::size_t n, KeyOf key) {
  std::vector<T, BigAllocator<T>> tmp(n);
  if (n < (std::size_t{1} << 16)) {
    radix_sort_serial(a, tmp.data(), n, key);
    return;
  }
  constexpr std::size_t kParts = 4;
  std::size_t cut[kParts + 1];
  for (std::size_t k = 0; k <= kParts; ++k) cut[k] = n * k / kParts;
  tbb::parallel_for(std::size_t{0}, kParts, [&](std::size_t k) {
    radix_sort_serial(a + cut[k], tmp.data() + cut[k], cut[k + 1] - cut[k], key);
  });
  const auto less = [&](const T& x, const T& y) { return key(x) < key(y); };
  tbb::parallel_for(std::size_t{0}, std::size_t{2}, [&](std::size_t k) {
    std::merge(a + cut[2 * k], a + cut[2 * k + 1], a + cut[2 * k + 1], a + cut[2 * k + 2],
               tmp.data() + cut[2 * k], less);
  });
  std::merge(tmp.data(), tmp.data() + cut[2], tmp.data() + cut[2], tmp.data() + n, a, less);
}

}  // namespace iaa::detail
