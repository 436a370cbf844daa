#include "cshapes/mesh/knn_graph.h"

#include <algorithm>
#include <cstdint>
#include <utility>
#include <vector>

#include "cshapes/support/error.h"
#include "cshapes/mesh/point_kdtree.h"

namespace cshapes {

Edges knn_graph(const Points& P, const KnnGraphOptions& options) {
  check_limit(kKnnLimit, options.k, "knn_graph");
  const Index n = P.rows();
  for (Index i = 0; i < n; ++i)
    CSHAPES_REQUIRE(P.row(i).allFinite(), "knn_graph: point ", i,
                    " has a non-finite coordinate (NaN or Inf)");
  if (n < 2) return Edges(0, 2);

  const Index k = std::min<Index>(options.k, n - 1);
  PointsKdAdaptor adaptor{P};
  PointsKdTree tree(3, adaptor, nanoflann::KDTreeSingleIndexAdaptorParams(10));
  std::vector<std::pair<int, int>> pairs(static_cast<size_t>(n * k));

#pragma omp parallel
  {
    // k+1: the query point finds itself (distance 0) among its own neighbours.
    std::vector<uint32_t> found(k + 1);
    std::vector<double> squared_distance(k + 1);  // nanoflann returns SQUARED distances
#pragma omp for schedule(static)
    for (Index i = 0; i < n; ++i) {
      const double query[3] = {P(i, 0), P(i, 1), P(i, 2)};
      size_t count = tree.knnSearch(query, static_cast<size_t>(k + 1), found.data(), squared_distance.data());
      // Drop the point itself; when duplicates of it crowd it out of the k+1, drop the farthest instead.
      auto self = std::find(found.begin(), found.begin() + count, static_cast<uint32_t>(i));
      if (self != found.begin() + count) std::copy(self + 1, found.begin() + count, self);
      for (Index j = 0; j < k; ++j) {
        int a = static_cast<int>(i), b = static_cast<int>(found[j]);
        pairs[i * k + j] = {std::min(a, b), std::max(a, b)};
      }
    }
  }
  std::sort(pairs.begin(), pairs.end());
  pairs.erase(std::unique(pairs.begin(), pairs.end()), pairs.end());
  Edges E(static_cast<Index>(pairs.size()), 2);
  for (size_t e = 0; e < pairs.size(); ++e) E.row(static_cast<Index>(e)) << pairs[e].first, pairs[e].second;
  return E;
}

}  // namespace cshapes
