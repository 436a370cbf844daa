// The all-pairs shape-distance matrix of a set of canonical forms (the paper's Fig. 7 and retrieval
// experiment): every pair aligned by ICP and measured (shape_distance.h), OpenMP over pairs, split over the
// ranks of a distributed run (support/communicator.h), finished pairs cached on disk (cache.h) in packs of many
// pairs, so a killed run resumes without recomputing what was stored.
//
// A pair is identified by the two shapes' content keys (the shape with the smaller key is aligned onto the
// other, so the order of the list does not matter) and to_key_string(icp options). A shape's content key is
// whatever the caller says identifies it — typically cache_key({file_content_hash(input mesh), canonization
// options}) — or, by default, the SHA-256 of its coordinates (points_content_key).
//
// Cache layout (cache_dir): packs/ab/<sha256>.bin, each a CBOR table of finished pairs (the two shape keys,
// the three distances, the reflection flag, ICP's iterations, rotation and translation), named by the SHA-256
// of its content and written atomically (equal packs from two writers are one file). One file per
// `pack_pairs` pairs instead of one per pair: at N = 200, 20 files instead of 19,900 (file creation took 4%
// of the run, and a cluster's shared file system counts files, not bytes). The older one-entry-per-pair
// layout (ab/<key>.bin, "pairwise-distance-1") is still read, never written.
//
// Distributed (options.communicator with R > 1 ranks): rank 0 reads the cache and broadcasts which pairs are
// missing; the missing pairs, in row order, are split into R contiguous blocks of equal count; each rank
// aligns its block and stores it in the cache; the matrices are summed onto rank 0 (each entry has exactly
// one non-zero contribution, so the sum is exact and the result bit-identical to one process).
//
// Cost: N(N−1)/2 alignments of ~12 ms each for 5,000-point shapes (3.5 ms for 1,000 points): 94% of a
// profile at N = 200 was ICP's nearest-neighbour search and steps. Besides that: one IcpShape per shape, and
// the cache (reading 19,900 cached pairs from packs: 0.6 s).
#pragma once

#include <string>
#include <utility>
#include <vector>

#include "cshapes/support/communicator.h"
#include "cshapes/support/progress.h"
#include "cshapes/support/types.h"
#include "cshapes/matching/icp.h"

namespace cshapes {

struct PairwiseDistanceOptions {
  IcpOptions icp;         // alignment of each pair (IcpOptions::parallel is ignored: pairs run in parallel)
  std::string cache_dir;  // on-disk cache of pair results; empty: no cache
  int threads = 0;        // OpenMP threads over pairs; 0: OpenMP's default
  ProgressFn progress;    // stage "distances", called as pairs finish (from one thread at a time)
  // The pairs to measure, (i, j) with i ≠ j in either order (a pair listed twice counts once); empty: all
  // N(N−1)/2. Entries of pairs not listed are NaN in the result (two-stage retrieval,
  // eval/candidate_pairs.h).
  std::vector<std::pair<int, int>> only_pairs;
  // Finished pairs are written to the cache together: one pack per pack_pairs pairs or per pack_seconds of
  // work (whichever comes first), and whatever is left when the call ends or fails. A process killed with
  // no chance to clean up loses at most that much work; a throwing one loses nothing.
  long pack_pairs = 1000;
  double pack_seconds = 60;
  // The ranks sharing the work; nullptr: this process alone. Every rank calls with the same shapes, keys and
  // options; the cache directory must be one that every rank sees (a shared file system across nodes).
  const Communicator* communicator = nullptr;
  // Test hook simulating a killed run: throw cshapes::Error once this many pairs have been computed and
  // stored in this call on this rank (cached pairs do not count). Negative: never.
  long fail_after_computed = -1;
};

struct PairwiseDistanceResult {
  // N×N, symmetric, zero diagonal (shape_distance.h): hausdorff is the paper's distance; NaN for pairs not
  // in only_pairs. Complete on rank 0 only: other ranks of a distributed run get 0×0 matrices.
  Eigen::MatrixXd hausdorff, chamfer, rmse;
  Eigen::MatrixXi reflection;  // 1 where the best alignment was a reflection
  long pairs = 0;              // pairs measured: N(N−1)/2, or the distinct pairs of only_pairs
  long computed = 0;           // pairs aligned in this call (cache misses), summed over ranks
  long cached = 0;             // pairs read from the cache (hits)
  double seconds = 0;
};

// shapes: N point sets (canonical forms); rows with a non-finite coordinate (vertices a repair dropped) are
// left out of the alignment and the distances. keys: N content keys, or empty to hash the coordinates.
// Any finite scale: when a shape lies outside ICP's sizes (icp_size_refusal), every shape is aligned
// multiplied by the power of two that brings the largest to unit size, and the results are given in the
// shapes' own units (a set scaled by s gives its matrix scaled by s, to rounding). Throws naming the shape
// (its index) when ICP cannot take it at any size (icp_points_refusal: on a line, at one point) or when it is
// more than about 1e140 times smaller than the largest.
// Throws on invalid input, and rethrows the first error of any pair (pairs finished before it stay cached);
// distributed, every rank throws when any rank failed (the failing rank its own error).
PairwiseDistanceResult pairwise_distances(const std::vector<Points>& shapes,
                                          const std::vector<std::string>& keys,
                                          const PairwiseDistanceOptions& options = {});

// SHA-256 of the row count and the coordinates' bytes: equal points, equal key.
std::string points_content_key(const Points& X);

}  // namespace cshapes
