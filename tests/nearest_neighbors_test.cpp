#include "cshapes/matching/nearest_neighbors.h"

#include <gtest/gtest.h>

#include <cstring>
#include <random>

#include "cshapes/support/error.h"
#include "cshapes/support/simd.h"

namespace cshapes {
namespace nearest_neighbors_test {

Points random_points(Index n, uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  Points X(n, 3);
  for (Index i = 0; i < n; ++i) X.row(i) = Eigen::RowVector3d(u(rng), 3 * u(rng), 0.5 * u(rng));
  return X;
}

TEST(NearestNeighbors, MatchesBruteForce) {
  Points X = random_points(1000, 1), Q = random_points(300, 2) * 1.3;
  NearestNeighbors tree(X);
  EXPECT_EQ(tree.size(), 1000);
  Eigen::VectorXi index;
  Eigen::VectorXd d2;
  tree.nearest_all(Q, index, d2);
  for (Index q = 0; q < Q.rows(); ++q) {
    Index best = 0;
    double best_d2 = (X.rowwise() - Q.row(q)).rowwise().squaredNorm().minCoeff(&best);
    EXPECT_DOUBLE_EQ(d2[q], best_d2);  // squared, as documented
    EXPECT_EQ(index[q], best);
    double single = 0;
    EXPECT_EQ(tree.nearest(Q.row(q).transpose(), &single), best);
    EXPECT_DOUBLE_EQ(single, best_d2);
  }
}

TEST(NearestNeighbors, MatchesBruteForceWhateverTheSize) {
  // Leaves hold a fixed number of points and the last one is padded: every remainder, and queries both
  // among the points and far from them, with and without a hint.
  for (Index n :
       {1, 2, 3, 4, 5, 7, 8, 9, 15, 16, 17, 31, 63, 64, 65, 72, 100, 127, 128, 129, 200, 4999, 5000}) {
    Points X = random_points(n, 100 + static_cast<uint64_t>(n)), Q = random_points(40, 7) * 1.5;
    Q.topRows(std::min<Index>(10, n)) = X.topRows(std::min<Index>(10, n));  // exact hits, distance 0
    NearestNeighbors tree(X);
    for (Index q = 0; q < Q.rows(); ++q) {
      Index best = 0;
      double best_d2 = (X.rowwise() - Q.row(q)).rowwise().squaredNorm().minCoeff(&best);
      double d2 = -1;
      EXPECT_EQ(tree.nearest(Q.row(q).transpose(), &d2), best) << "n = " << n << ", query " << q;
      EXPECT_DOUBLE_EQ(d2, best_d2);
      EXPECT_EQ(tree.nearest(Q.row(q).transpose(), n - 1 - best / 2, &d2), best) << "n = " << n;
      EXPECT_DOUBLE_EQ(d2, best_d2);
    }
  }
}

TEST(NearestNeighbors, RepeatedCoordinatesAndDuplicatePoints) {
  // A 12×12×12 integer grid (every coordinate value shared by 144 points) plus every point again: the
  // tree's median splits meet long runs of equal keys. Ties make the index ambiguous, so check that the
  // returned point attains the brute-force distance.
  Points X(2 * 1728, 3);
  for (Index i = 0; i < 1728; ++i)
    X.row(i) = X.row(1728 + i) = Eigen::RowVector3d(
        static_cast<double>(i % 12), static_cast<double>(i / 12 % 12), static_cast<double>(i / 144));
  NearestNeighbors tree(X);
  Points Q = random_points(200, 8) * 8;
  Q.array() += 5.5;
  for (Index q = 0; q < Q.rows(); ++q) {
    const double best_d2 = (X.rowwise() - Q.row(q)).rowwise().squaredNorm().minCoeff();
    double d2 = -1;
    const Index found = tree.nearest(Q.row(q).transpose(), &d2);
    EXPECT_DOUBLE_EQ(d2, best_d2);
    EXPECT_DOUBLE_EQ((X.row(found) - Q.row(q)).squaredNorm(), best_d2);
  }
}

TEST(NearestNeighbors, HintedSearchIsExact) {
  // Any hint, good or bad, gives the exact nearest point (the hint only bounds the search).
  Points X = random_points(2000, 4), Q = random_points(200, 5) * 1.2;
  NearestNeighbors tree(X);
  std::mt19937_64 rng(6);
  std::uniform_int_distribution<int> any(0, 1999);
  for (Index q = 0; q < Q.rows(); ++q) {
    Index best = 0;
    double best_d2 = (X.rowwise() - Q.row(q)).rowwise().squaredNorm().minCoeff(&best);
    for (Index hint : {best, static_cast<Index>(any(rng)), static_cast<Index>(any(rng))}) {
      double d2 = -1;
      EXPECT_EQ(tree.nearest(Q.row(q).transpose(), hint, &d2), best);
      EXPECT_DOUBLE_EQ(d2, best_d2);
    }
  }
}

TEST(NearestNeighbors, PointsThemselvesAreTheirOwnNeighbours) {
  Points X = random_points(500, 3);
  NearestNeighbors tree(X);
  Eigen::VectorXi index;
  Eigen::VectorXd d2;
  tree.nearest_all(X, index, d2, true);
  for (Index i = 0; i < X.rows(); ++i) {
    EXPECT_EQ(index[i], i);
    EXPECT_EQ(d2[i], 0.0);
  }
}

// The search is compiled per instruction set (support/simd.h): each target this CPU has finds the same point
// at the same squared distance, to the bit, with and without a hint, among repeated points (ties) and padded
// leaves too; ICP and the shape distances rest on it being so.
TEST(NearestNeighbors, EveryInstructionSetGivesTheSameBytes) {
  Points X = random_points(1237, 5);
  X.bottomRows(200) = X.topRows(200);             // duplicate points: ties between leaves
  X.col(2).segment(300, 100).setConstant(0.25);   // repeated coordinates
  const Points Q = random_points(700, 6) * 1.2;
  const SimdTarget before = simd_target();
  std::vector<Eigen::VectorXi> indices;
  std::vector<Eigen::VectorXd> distances;
  std::vector<std::vector<Index>> hinted;
  for (SimdTarget target : supported_simd_targets()) {
    set_simd_target(target);
    const NearestNeighbors tree(X);
    Eigen::VectorXi index;
    Eigen::VectorXd d2;
    tree.nearest_all(Q, index, d2);
    std::vector<Index> h;
    for (Index q = 0; q < Q.rows(); ++q) {
      double d = 0;
      h.push_back(tree.nearest(Q.row(q).transpose(), (q * 7919) % X.rows(), &d));
      EXPECT_EQ(d, d2[q]) << to_string(target) << " query " << q;
    }
    indices.push_back(index);
    distances.push_back(d2);
    hinted.push_back(h);
  }
  set_simd_target(before);
  for (size_t k = 1; k < indices.size(); ++k) {
    EXPECT_EQ(indices[k], indices[0]) << "target " << k;
    EXPECT_EQ(std::memcmp(distances[k].data(), distances[0].data(), sizeof(double) * distances[0].size()), 0)
        << "target " << k;
    EXPECT_EQ(hinted[k], hinted[0]) << "target " << k;
  }
}

TEST(NearestNeighbors, SinglePointAndEmptyInput) {
  Points one(1, 3);
  one << 1, 2, 3;
  NearestNeighbors tree(one);
  double d2 = -1;
  EXPECT_EQ(tree.nearest(Eigen::Vector3d(1, 2, 5), &d2), 0);
  EXPECT_DOUBLE_EQ(d2, 4.0);
  EXPECT_THROW(NearestNeighbors(Points(0, 3)), Error);
  Points bad = one;
  bad(0, 1) = std::numeric_limits<double>::quiet_NaN();
  EXPECT_THROW(NearestNeighbors{bad}, Error);
}

}  // namespace nearest_neighbors_test
}  // namespace cshapes
