// The symmetric k-nearest-neighbour graph of a point cloud: the edges that stand in for a mesh's edges when
// the input has no faces, so every stage that needs only edges and rest lengths (edge_lengths) works on point
// clouds too (the paper's "future work").
#pragma once

#include "cshapes/support/option_fields.h"
#include "cshapes/support/option_limits.h"

#include "cshapes/support/types.h"

namespace cshapes {

// The limit of k as a user sets it (`--knn`, knn=; support/option_limits.h).
inline constexpr Limit kKnnLimit = integer_limit("knn", 1, 1000);

struct KnnGraphOptions {
  int k =
      8;  // neighbours per point (other points; a duplicate of a point counts as a neighbour at distance 0)

  // Every field by name, for cache keys (support/option_fields.h). Self: KnnGraphOptions, const or not.
  template <class Self, class Visit>
  static void for_each_field(Self& o, Visit&& visit) {
    visit("k", o.k);
  }
};

// Edges (i, j), i < j, sorted lexicographically and unique, with no self edges, joining every point to its k
// nearest other points in Euclidean distance (the union of the relations, so the graph is symmetric: a point
// may have more than k neighbours, never fewer than min(k, n-1)). With k >= n-1 the graph is complete.
// Ties at equal distance are broken arbitrarily. P: n×3, finite coordinates (throws cshapes::Error otherwise,
// and for k < 1). Empty or one-point input gives no edges.
// Cost: O(n log n) to build a KD-tree (nanoflann) and O(n k log n) for the queries, in parallel (OpenMP).
Edges knn_graph(const Points& P, const KnnGraphOptions& options = {});

}  // namespace cshapes
