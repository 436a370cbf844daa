#include "cshapes/mesh/knn_graph.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <limits>
#include <random>
#include <set>
#include <utility>
#include <vector>

#include "cshapes/support/error.h"
#include "cshapes/data/synthetic.h"

namespace cshapes {
namespace knn_graph_test {

Points random_points(int n, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> uniform(-1.0, 1.0);
  Points P(n, 3);
  for (int i = 0; i < n; ++i)
    for (int c = 0; c < 3; ++c) P(i, c) = uniform(rng);
  return P;
}

// The definition, by brute force: every point joined to its k nearest other points (by sorting all
// distances).
Edges brute_force_knn_graph(const Points& P, int k) {
  const int n = static_cast<int>(P.rows());
  std::set<std::pair<int, int>> edges;
  for (int i = 0; i < n; ++i) {
    std::vector<std::pair<double, int>> by_distance;
    for (int j = 0; j < n; ++j)
      if (j != i) by_distance.emplace_back((P.row(i) - P.row(j)).squaredNorm(), j);
    std::sort(by_distance.begin(), by_distance.end());
    for (int m = 0; m < std::min<int>(k, n - 1); ++m)
      edges.emplace(std::min(i, by_distance[m].second), std::max(i, by_distance[m].second));
  }
  Edges E(edges.size(), 2);
  int e = 0;
  for (const auto& [i, j] : edges) E.row(e++) << i, j;
  return E;
}

void expect_well_formed(const Edges& E, Index n) {
  for (Index e = 0; e < E.rows(); ++e) {
    EXPECT_LT(E(e, 0), E(e, 1));
    EXPECT_GE(E(e, 0), 0);
    EXPECT_LT(E(e, 1), n);
    if (e > 0) {
      EXPECT_TRUE(E(e - 1, 0) < E(e, 0) || (E(e - 1, 0) == E(e, 0) && E(e - 1, 1) < E(e, 1))) << "row " << e;
    }
  }
}

TEST(KnnGraph, MatchesBruteForceOnRandomPoints) {
  // Random points have distinct distances (with probability 1), so the graph is unique.
  for (int n : {2, 3, 17, 300}) {
    Points P = random_points(n, 1234u + n);
    for (int k : {1, 2, 5, 8, n - 2, n - 1, n, n + 5}) {
      if (k < 1) continue;
      SCOPED_TRACE(testing::Message() << "n=" << n << " k=" << k);
      KnnGraphOptions options;
      options.k = k;
      Edges E = knn_graph(P, options);
      expect_well_formed(E, n);
      EXPECT_TRUE(E == brute_force_knn_graph(P, k));
    }
  }
}

TEST(KnnGraph, CompleteGraphWhenKReachesNMinusOne) {
  const int n = 12;
  KnnGraphOptions options;
  options.k = n - 1;
  EXPECT_EQ(knn_graph(random_points(n, 7), options).rows(), n * (n - 1) / 2);
}

TEST(KnnGraph, EmptyAndSinglePointGiveNoEdges) {
  EXPECT_EQ(knn_graph(Points(0, 3)).rows(), 0);
  EXPECT_EQ(knn_graph(random_points(1, 3)).rows(), 0);
}

TEST(KnnGraph, DuplicatePointsAreNeighboursWithoutSelfEdges) {
  // Each point three times: with k = 2 a point's nearest others are exactly its two copies.
  Points base = random_points(40, 11);
  const int n = 3 * static_cast<int>(base.rows());
  Points P(n, 3);
  for (int i = 0; i < n; ++i) P.row(i) = base.row(i % base.rows());
  KnnGraphOptions options;
  options.k = 2;
  Edges E = knn_graph(P, options);
  expect_well_formed(E, n);
  EXPECT_EQ(E.rows(), n);  // one triangle of copies per base point
  for (Index e = 0; e < E.rows(); ++e) EXPECT_EQ(E(e, 0) % base.rows(), E(e, 1) % base.rows());
  // With k = 5 every point reaches beyond its copies; each has at least 5 neighbours, all of them as near as
  // the brute-force 5th nearest distance (ties among copies may be broken either way).
  options.k = 5;
  E = knn_graph(P, options);
  expect_well_formed(E, n);
  std::vector<std::vector<int>> neighbours(n);
  for (Index e = 0; e < E.rows(); ++e) {
    neighbours[E(e, 0)].push_back(E(e, 1));
    neighbours[E(e, 1)].push_back(E(e, 0));
  }
  for (int i = 0; i < n; ++i) {
    std::vector<double> d;
    for (int j = 0; j < n; ++j)
      if (j != i) d.push_back((P.row(i) - P.row(j)).squaredNorm());
    std::nth_element(d.begin(), d.begin() + 4, d.end());
    const double fifth = d[4];
    int within = 0;
    for (int j : neighbours[i]) within += (P.row(i) - P.row(j)).squaredNorm() <= fifth;
    EXPECT_GE(within, 5) << "point " << i;
  }
}

TEST(KnnGraph, MeshVerticesGetTheirNearestNeighbours) {
  // On an icosphere every vertex's nearest other vertex is a mesh neighbour: the k = 1 graph is a
  // subset of the mesh edges.
  Mesh sphere = icosphere(2);
  KnnGraphOptions options;
  options.k = 1;
  Edges knn = knn_graph(sphere.V, options);
  Edges mesh = mesh_edges(sphere.F);
  std::set<std::pair<int, int>> mesh_set;
  for (Index e = 0; e < mesh.rows(); ++e) mesh_set.emplace(mesh(e, 0), mesh(e, 1));
  for (Index e = 0; e < knn.rows(); ++e) EXPECT_TRUE(mesh_set.count({knn(e, 0), knn(e, 1)})) << knn.row(e);
}

TEST(KnnGraph, RefusesBadInput) {
  KnnGraphOptions options;
  options.k = 0;
  EXPECT_THROW(knn_graph(random_points(5, 1), options), Error);
  Points P = random_points(5, 1);
  P(2, 1) = std::numeric_limits<double>::quiet_NaN();
  EXPECT_THROW(knn_graph(P), Error);
}

}  // namespace knn_graph_test
}  // namespace cshapes
