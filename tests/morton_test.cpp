#include "cshapes/support/morton.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <random>
#include <utility>
#include <vector>

namespace cshapes {
namespace morton_test {

using Items = std::vector<std::pair<uint64_t, int32_t>>;

// (key, index) pairs in index order, keys drawn from `key_of`.
template <class KeyOf>
Items items_of(int n, KeyOf key_of) {
  Items items(n);
  for (int i = 0; i < n; ++i) items[i] = {key_of(i), i};
  return items;
}

// The radix sort gives std::sort's order of the pairs: keys spread over all 63 bits, keys that share their
// high digits (passes skipped), many equal keys (stability), and the empty and single-item cases.
TEST(Morton, RadixSortIsTheComparisonSortOfThePairs) {
  std::mt19937_64 rng(5);
  std::uniform_int_distribution<uint64_t> any(0, (uint64_t(1) << 63) - 1);
  std::uniform_int_distribution<uint64_t> low(0, 5000);
  const std::vector<Items> cases = {
      items_of(20000, [&](int) { return any(rng); }),
      items_of(20000, [&](int) { return (uint64_t(0x5a5) << 50) | low(rng); }),  // high digits constant
      items_of(20000, [&](int) { return low(rng) % 7; }),                         // few distinct keys
      items_of(3000, [&](int i) { return uint64_t(3000 - i); }),                 // reversed
      items_of(20000, [&](int) { return uint64_t(42); }),                        // one key: every pass skipped
      Items{},
      items_of(1, [&](int) { return uint64_t(7); }),
  };
  for (const Items& input : cases) {
    Items radix = input, reference = input;
    radix_sort_by_key(radix, 63);
    std::sort(reference.begin(), reference.end());
    EXPECT_EQ(radix, reference) << input.size() << " items";
  }
}

// Morton codes interleave the three coordinates' bits: x in bit 3k + 2, y in 3k + 1, z in 3k (the FMM's and
// ICP's convention: spread(x) << 2 | spread(y) << 1 | spread(z)).
TEST(Morton, SpreadBitsPutsBitKAtBit3K) {
  for (int k = 0; k < 21; ++k) EXPECT_EQ(morton_spread_bits(uint64_t(1) << k), uint64_t(1) << (3 * k));
  EXPECT_EQ(morton_spread_bits(0x1fffff), 0x1249249249249249ULL);
  EXPECT_EQ(morton_spread_bits(uint64_t(1) << 21), 0u);  // bits above 21 are dropped
}

}  // namespace morton_test
}  // namespace cshapes
