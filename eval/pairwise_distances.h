// The all-pairs shape-distance matrix of a set of canonical forms (the paper's Fig. 7 and retrieval
// experiment): every pair aligned by ICP and measured (shape_distance.h), OpenMP over pairs, each pair
// cached on disk (cache.h) as soon as it is computed, so a killed run resumes without recomputing.
//
// A pair's cache key is built from the two shapes' content keys (sorted, so the order of the list does not
// matter) and to_key_string(icp options); the shape with the smaller key is aligned onto the other.
// A shape's content key is whatever the caller says identifies it — typically
// cache_key({file_content_hash(input mesh), canonization options}) — or, by default, the SHA-256 of its
// coordinates (points_content_key).
//
// Cost: N(N−1)/2 alignments of ~20 ms each for 5,000-point shapes (190 pairs: ~4 s on one core).
#pragma once

#include <string>
#include <vector>

#include "core/progress.h"
#include "core/types.h"
#include "matching/icp.h"

namespace cshapes {

struct PairwiseDistanceOptions {
  IcpOptions icp;         // alignment of each pair (IcpOptions::parallel is ignored: pairs run in parallel)
  std::string cache_dir;  // on-disk cache of pair results; empty: no cache
  int threads = 0;        // OpenMP threads over pairs; 0: OpenMP's default
  ProgressFn progress;    // stage "distances", called as pairs finish (from one thread at a time)
  // Test hook simulating a killed run: throw cshapes::Error once this many pairs have been computed and
  // stored in this call (cached pairs do not count). Negative: never.
  long fail_after_computed = -1;
};

struct PairwiseDistanceResult {
  // N×N, symmetric, zero diagonal (shape_distance.h): hausdorff is the paper's distance.
  Eigen::MatrixXd hausdorff, chamfer, rmse;
  Eigen::MatrixXi reflection;  // 1 where the best alignment was a reflection
  long pairs = 0;              // N(N−1)/2
  long computed = 0;           // pairs aligned in this call (cache misses)
  long cached = 0;             // pairs read from the cache (hits)
  double seconds = 0;
};

// shapes: N point sets (canonical forms); rows with a non-finite coordinate (vertices a repair dropped) are
// left out of the alignment and the distances. keys: N content keys, or empty to hash the coordinates.
// Throws on invalid input, and rethrows the first error of any pair (pairs finished before it stay cached).
PairwiseDistanceResult pairwise_distances(const std::vector<Points>& shapes,
                                          const std::vector<std::string>& keys,
                                          const PairwiseDistanceOptions& options = {});

// SHA-256 of the row count and the coordinates' bytes: equal points, equal key.
std::string points_content_key(const Points& X);

}  // namespace cshapes
