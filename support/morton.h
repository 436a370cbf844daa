// Morton (Z-order) codes and a stable radix sort by them, shared by the FMM's octree (canon/coulomb_fmm) and
// ICP's spatial order of points (matching/icp).
#pragma once

#include <algorithm>
#include <cstdint>
#include <utility>
#include <vector>

namespace cshapes {

// Bits per axis of a Morton key of three coordinates (63 bits in all): what morton_spread_bits takes.
inline constexpr int kMortonLevels = 21;

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
// pass, every pass's histogram counted in one read before the first: O(n) and stable, so pairs in index order
// come out in the order std::sort gives the pairs — deterministic, at a fraction of a comparison sort's cost.
// A pass whose digit is the same for every key is skipped (it would not move anything).
// scratch: a buffer to use (and keep) instead of allocating one, for callers that sort again and again.
inline void radix_sort_by_key(std::vector<std::pair<uint64_t, int32_t>>& items, int key_bits,
                              std::vector<std::pair<uint64_t, int32_t>>* scratch = nullptr) {
  constexpr int kBits = 11, kBuckets = 1 << kBits, kMaxPasses = (64 + kBits - 1) / kBits;
  const int passes = std::min(kMaxPasses, (key_bits + kBits - 1) / kBits);
  if (items.size() > UINT32_MAX) {  // beyond the counters' range: the same order by a stable comparison sort
    const uint64_t mask = key_bits >= 64 ? ~uint64_t(0) : (uint64_t(1) << key_bits) - 1;
    std::stable_sort(items.begin(), items.end(),
                     [mask](const auto& a, const auto& b) { return (a.first & mask) < (b.first & mask); });
    return;
  }
  std::vector<uint32_t> counts(static_cast<size_t>(passes) * kBuckets, 0);
  for (const auto& item : items)
    for (int p = 0; p < passes; ++p) ++counts[p * kBuckets + ((item.first >> (p * kBits)) & (kBuckets - 1))];
  std::vector<std::pair<uint64_t, int32_t>> own;
  std::vector<std::pair<uint64_t, int32_t>>& buffer = scratch ? *scratch : own;
  buffer.resize(items.size());
  std::vector<size_t> offset(kBuckets);
  for (int p = 0; p < passes; ++p) {
    const uint32_t* count = counts.data() + p * kBuckets;
    if (std::any_of(count, count + kBuckets, [&](uint32_t c) { return c == items.size(); })) continue;
    size_t total = 0;
    for (int b = 0; b < kBuckets; ++b) offset[b] = total, total += count[b];
    const int shift = p * kBits;
    for (const auto& item : items) buffer[offset[(item.first >> shift) & (kBuckets - 1)]++] = item;
    items.swap(buffer);
  }
}

}  // namespace cshapes
