// eval/candidate_pairs.h on points of a line, where every answer can be worked out by hand.
#include "cshapes/eval/candidate_pairs.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "cshapes/support/error.h"

namespace cshapes {
namespace candidate_pairs_test {

// |x_i − x_j| for x = 0, 1, 3, 7, 8.
Eigen::MatrixXd line_distances() {
  Eigen::VectorXd x(5);
  x << 0, 1, 3, 7, 8;
  Eigen::MatrixXd D(5, 5);
  for (int i = 0; i < 5; ++i)
    for (int j = 0; j < 5; ++j) D(i, j) = std::abs(x[i] - x[j]);
  return D;
}

TEST(CandidatePairs, NearestCandidatesKnownAnswer) {
  const auto c = nearest_candidates(line_distances(), 2);
  ASSERT_EQ(c.size(), 5u);
  EXPECT_EQ(c[0], (std::vector<int>{1, 2}));
  EXPECT_EQ(c[2], (std::vector<int>{1, 0}));  // 2 and 3 away; 7 is 4 away
  EXPECT_EQ(c[3], (std::vector<int>{4, 2}));
  // Ties go to the lower index; k beyond N−1 takes everyone else.
  Eigen::MatrixXd flat = Eigen::MatrixXd::Ones(4, 4);
  EXPECT_EQ(nearest_candidates(flat, 2)[3], (std::vector<int>{0, 1}));
  EXPECT_EQ(nearest_candidates(flat, 9)[1], (std::vector<int>{0, 2, 3}));
  EXPECT_THROW(nearest_candidates(flat, 0), Error);
}

TEST(CandidatePairs, UnionHoldsEachPairOnce) {
  const auto pairs = candidate_pairs(nearest_candidates(line_distances(), 1));
  // Nearest: 0→1, 1→0, 2→1, 3→4, 4→3: pairs (0,1), (1,2), (3,4).
  EXPECT_EQ(pairs, (std::vector<std::pair<int, int>>{{0, 1}, {1, 2}, {3, 4}}));
}

TEST(CandidatePairs, UnmeasuredPairsRankLast) {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  Eigen::MatrixXd D(3, 3);
  D << 0, 2, nan, 2, 0, 5, nan, 5, 0;
  Eigen::MatrixXd delta(3, 3);
  delta << 0, 0.1, 0.5, 0.1, 0, 0.2, 0.5, 0.2, 0;
  rank_unmeasured_last(D, delta);
  EXPECT_EQ(D(0, 2), 5 * 1.5);  // the largest measured (5) times 1 + δ
  EXPECT_EQ(D(2, 0), D(0, 2));
  EXPECT_EQ(D(0, 1), 2);
  Eigen::MatrixXd none = Eigen::MatrixXd::Constant(2, 2, nan);
  none.diagonal().setZero();
  EXPECT_THROW(rank_unmeasured_last(none, Eigen::MatrixXd::Zero(2, 2)), Error);
}

TEST(CandidatePairs, RecallAgainstTheReference) {
  const Eigen::MatrixXd D = line_distances();
  EXPECT_EQ(candidate_recall(D, nearest_candidates(D, 2)), 1.0);
  // Candidates far from every query: none of them is among its true two nearest.
  std::vector<std::vector<int>> farthest = {{4, 3}, {4, 3}, {4, 3}, {0, 1}, {0, 1}};
  EXPECT_EQ(candidate_recall(D, farthest), 0.0);
  // One of two right for query 0, the rest perfect: (0.5 + 4) / 5.
  auto some = nearest_candidates(D, 2);
  some[0] = {1, 4};
  EXPECT_DOUBLE_EQ(candidate_recall(D, some), 0.9);
}

}  // namespace candidate_pairs_test
}  // namespace cshapes
