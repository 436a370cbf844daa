// Morton (Z-order) codes and a stable radix sort by them, shared by the FMM's octree (canon/coulomb_fmm) and
// ICP's spatial order of points (matching/icp).
#pragma once

#include <algorithm>
#include <cstdint>
#include <utility>
#include <vector>

namespace cshapes {

// The low 21 bits of v spread to every third bit (bit k → bit 3k): interleave three of them, shifted by 0, 1
// and 2, into one 63-bit Morton code.
inline uint64_t morton_spread_bits(uint64_t v) {
  v &= 0x1fffff;
  v = (v | v << 32) & 0x1f00000000ffffULL;
  v = (v | v << 16) & 0x1f0000ff0000ffULL;
  v = (v | v << 8) & 0x100f00f00f00f00fULL;
  v = (v | v << 4) & 0x10c30c30c30c30c3ULL;
  v = (v | v << 2) & 0x1249249249249249ULL;
  return v;
}

// Sorts (key, index) pairs by the low key_bits bits of the key. Least-significant-digit radix sort, 11 bits a
// pass: O(n) and stable, so pairs in index order come out in the order std::sort gives the pairs —
// deterministic, at a fraction of a comparison sort's cost.
inline void radix_sort_by_key(std::vector<std::pair<uint64_t, int32_t>>& items, int key_bits) {
  constexpr int kBits = 11, kBuckets = 1 << kBits;
  std::vector<std::pair<uint64_t, int32_t>> buffer(items.size());
  std::vector<size_t> offset(kBuckets);
  for (int shift = 0; shift < key_bits; shift += kBits) {
    std::fill(offset.begin(), offset.end(), 0);
    for (const auto& item : items) ++offset[(item.first >> shift) & (kBuckets - 1)];
    size_t total = 0;
    for (size_t& o : offset) {
      const size_t c = o;
      o = total;
      total += c;
    }
    for (const auto& item : items) buffer[offset[(item.first >> shift) & (kBuckets - 1)]++] = item;
    items.swap(buffer);
  }
}

}  // namespace cshapes
