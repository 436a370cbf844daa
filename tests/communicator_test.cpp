// support/communicator.h: the one-process communicator leaves values alone, and the work splits are complete,
// balanced and known for small cases.
#include "cshapes/support/communicator.h"

#include <gtest/gtest.h>

#include "cshapes/support/error.h"

namespace cshapes {
namespace communicator_test {

TEST(Communicator, OneProcessIsRankZeroOfOne) {
  const Communicator& one = single_process();
  EXPECT_EQ(one.rank(), 0);
  EXPECT_EQ(one.size(), 1);
  EXPECT_TRUE(one.is_root());
  double values[2] = {1.5, -2};
  one.sum_to_all(values, 2);
  one.sum_to_root(values, 2);
  EXPECT_EQ(values[0], 1.5);
  EXPECT_EQ(values[1], -2);
  std::string bytes = "abc";
  one.broadcast_from_root(bytes);
  EXPECT_EQ(bytes, "abc");
  EXPECT_EQ(one.sum(7L), 7);
  EXPECT_TRUE(one.any(true));
  EXPECT_FALSE(one.any(false));
}

TEST(Communicator, ContiguousSharesCoverEveryItemOnce) {
  for (long count : {0L, 1L, 7L, 45L, 1000L})
    for (int ranks : {1, 2, 3, 8}) {
      long next = 0, shortest = count, longest = 0;
      for (int r = 0; r < ranks; ++r) {
        const ItemRange share = contiguous_share(count, ranks, r);
        EXPECT_EQ(share.begin, next);
        next = share.end;
        shortest = std::min(shortest, share.end - share.begin);
        longest = std::max(longest, share.end - share.begin);
      }
      EXPECT_EQ(next, count);
      EXPECT_LE(longest - shortest, 1);
    }
  EXPECT_EQ(contiguous_share(7, 3, 0).end, 3);  // 3, 2, 2
  EXPECT_EQ(contiguous_share(7, 3, 2).begin, 5);
  EXPECT_THROW(contiguous_share(7, 3, 3), Error);
}

TEST(Communicator, LongestFirstKnownAnswer) {
  // 5 → rank 0, 4 → rank 1, 3 → rank 1 (4 < 5), 3 → rank 0 (5 < 7), 3 → rank 1 (7 < 8): loads 8 and 10.
  EXPECT_EQ(longest_first_owners({5, 4, 3, 3, 3}, 2), (std::vector<int>{0, 1, 1, 0, 1}));
  // Ties between items go to the lower index first, ties between ranks to the lower rank.
  EXPECT_EQ(longest_first_owners({1, 1, 1, 1}, 2), (std::vector<int>{0, 1, 0, 1}));
  EXPECT_EQ(longest_first_owners({2, 9}, 1), (std::vector<int>{0, 0}));
  EXPECT_THROW(longest_first_owners({1}, 0), Error);
  EXPECT_THROW(longest_first_owners({-1}, 2), Error);
}

}  // namespace communicator_test
}  // namespace cshapes
