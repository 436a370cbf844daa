// Rigid alignment of two point sets by the iterative closest point method (ICP) [Besl & McKay 1992;
// Chen & Medioni 1992], as the paper uses it to compare canonical forms (§3: "canonizing the shape ...
// followed by ICP").
//
// The two sets may differ in size and in vertex order (canonical forms of two poses share neither).
// The result maps SOURCE onto TARGET: y ≈ R·x + t for corresponding x ∈ source, y ∈ target.
//
// Method
//   1. Starting poses. Both sets are centred on their centroids and their principal axes (eigenvectors of
//      the covariance, by decreasing variance) are matched, with every sign combination of the three
//      axes: 4 rotations, plus 4 reflections when allowed. MDS and Coulomb embeddings are defined only up to
//      a rigid motion AND a reflection, so reflections are tried by default. Extra starts: with
//      try_axis_swaps, the same with two principal axes exchanged (90° turns about each axis, guarding
//      against principal variances that nearly tie, where the axes' order is arbitrary); with try_identity,
//      the input pose with the centroids matched.
//   2. Coarse to fine. Every start runs `screening_iterations` ICP steps with a random subsample of
//      `pyramid[0]` points of each set as queries (their nearest neighbours searched among ALL points of the
//      other set, so a level's RMSE estimates the full one without bias); the `finalists` best continue to
//      convergence through the larger samples of `pyramid`; the best of them is refined to convergence on
//      all points. Subsamples are nested random subsets fixed by `seed`, drawn once per shape
//      (IcpShape), so repeated alignments are deterministic.
//   3. One ICP step: correspondences by nearest neighbour (KD-tree), source→target and, when symmetric,
//      target→source; optionally drop the worst `trim_fraction` of each direction (trimmed ICP,
//      Chetverikov et al. 2002) and pairs farther than max_correspondence_distance; then the closed-form
//      least-squares rigid motion of all kept pairs (Kabsch/Umeyama, mesh/rigid_transform.h, by a 3×3 SVD)
//      whose determinant is that of the start: a start that is a reflection stays a reflection.
//   4. Stop when the RMSE changes by less than relative_tolerance of itself, when it falls below
//      absolute_tolerance × (the target's RMS radius) (exact fit), or after max_iterations.
//
// Cost: one KD-tree per shape, O(n log n), built once (IcpShape); one step O((n_s + n_t) log n), each
// search bounded by the previous step's neighbour, and a level's first step reuses the neighbours that the
// previous (nested) level found at the same pose. For two 5,000-point TOSCA poses, aligning with all 9
// starts makes about 62,000 nearest-neighbour queries: 30% in screening and the 100-point level, 30% on the
// 1,000-point level, 40% in the 3 passes on all points (`cshapes bench icp` times it against Open3D).
#pragma once

#include "cshapes/support/option_limits.h"

#include <cstdint>
#include <limits>
#include <memory>
#include <string>
#include <vector>

#include "cshapes/support/option_fields.h"
#include "cshapes/support/progress.h"
#include "cshapes/mesh/rigid_transform.h"
#include "cshapes/support/types.h"
#include "cshapes/matching/nearest_neighbors.h"
#include "cshapes/support/option_declaration.h"

namespace cshapes {

// RigidTransform, random_rigid_transform and best_rigid_transform (the closed-form Kabsch/Umeyama fit) live
// in mesh/rigid_transform.h, included here for the callers of icp().

// The limits of the options a user sets (support/option_limits.h), named as on the command line (`cshapes
// align`).
namespace icp_limits {
inline constexpr Limit kTrim = number_limit("trim", 0, 0.9);
inline constexpr Limit kTolerance = number_limit("icp-tolerance", 0);
}  // namespace icp_limits

// The options a user sets, each declared once (support/option_declaration.h): `cshapes align`'s flags and the
// keywords of icp(), shape_distance() and distance_matrix() in Python, with one help text.
namespace icp_options {
inline const OptionDeclaration kNoReflections{"no_reflections", "--no-reflections",
                                              "rotations only (det R = +1); by default mirror images are "
                                              "tried too, as MDS embeddings are defined only up "
                                              "to a reflection"};
inline const OptionDeclaration kOneWay{"one_way", "--one-way",
                                       "match A to B only (by default both directions: A to B and B to A)"};
inline const OptionDeclaration kAxisSwaps{"axis_swaps", "--axis-swaps",
                                          "also start from the principal axes exchanged pairwise (for shapes "
                                          "whose principal variances nearly tie)"};
inline const OptionDeclaration kTrim{
    "trim", "--trim", "the fraction of the worst pairs dropped per direction at each step (trimmed ICP)",
    icp_limits::kTrim};
inline const OptionDeclaration kTolerance{
    "icp_tolerance", "--icp-tolerance",
    "ICP stops when the RMSE changes by less than this fraction of itself", icp_limits::kTolerance};
// In the order `cshapes align --help` lists them.
inline const std::vector<const OptionDeclaration*> kAll = {&kNoReflections, &kOneWay, &kAxisSwaps, &kTrim,
                                                           &kTolerance};
}  // namespace icp_options

struct IcpOptions {
  // Starting poses (see the method above).
  bool try_principal_axes = true;  // start from the matched principal axes (every sign combination)
  bool allow_reflections = true;   // also start from the 4 reflected principal-axis poses
  bool try_axis_swaps = false;     // also the principal-axis poses with two axes exchanged (×4 starts)
  bool try_identity = true;        // also the input pose, centroids matched (rotation only)

  // Coarse to fine.
  // Query subsample sizes per level, increasing; all points come last.
  std::vector<Index> pyramid = {100, 1000};
  int screening_iterations = 8;  // ICP steps per start on the coarsest level before ranking the starts
  int finalists = 2;             // starts carried to convergence on the finer subsamples
  uint64_t seed = 1;             // for the subsamples
  // Iterate on all points after the finest subsample. false: keep the finest subsample's transform (its
  // RMSE is an unbiased estimate of the full one) and only compute the final correspondences on all
  // points — about 25% faster for 5,000 points; on TOSCA pose pairs the Hausdorff distance moved by up
  // to 2% and the Chamfer distance by under 1% (see cshapes bench icp).
  bool refine_on_all_points = true;

  // Iterations.
  int max_iterations = 100;  // per start and level
  // Stop when |RMSE_k − RMSE_{k+1}| ≤ this × RMSE_k. 1e-3 moves the Hausdorff distance of TOSCA cat0 vs cat1
  // by 0.1% from its value at 1e-5, for half the time.
  double relative_tolerance = 1e-3;
  double absolute_tolerance = 1e-12;  // stop when RMSE ≤ this × RMS radius of the target (an exact fit)
  bool symmetric = true;              // match in both directions (source→target and target→source)
  double trim_fraction = 0.0;         // in [0, 0.9]: drop this fraction of the worst pairs per direction
  // Pairs farther apart than this (target units) are dropped; infinity keeps all.
  double max_correspondence_distance = std::numeric_limits<double>::infinity();

  // Run the starts on OpenMP threads (never inside a parallel region). Off by default: one alignment takes
  // ~12 ms, and on a loaded machine waiting threads cost more than they save; parallelise over pairs instead.
  bool parallel = false;
  // Polled (support/progress.h) before every ICP step and the final distances: where a stop (Ctrl-C in Python)
  // is heard. A step on all points of a million-point pair takes about a second, so a poll per step.
  ProgressFn progress;

  // Every field by name, for cache keys (support/option_fields.h). Self: IcpOptions, const or not.
  template <class Self, class Visit>
  static void for_each_field(Self& o, Visit&& visit) {
    visit("try_principal_axes", o.try_principal_axes);
    visit("allow_reflections", o.allow_reflections);
    visit("try_axis_swaps", o.try_axis_swaps);
    visit("try_identity", o.try_identity);
    visit("pyramid", o.pyramid);
    visit("screening_iterations", o.screening_iterations);
    visit("finalists", o.finalists);
    visit("seed", o.seed);
    visit("refine_on_all_points", o.refine_on_all_points);
    visit("max_iterations", o.max_iterations);
    visit("relative_tolerance", o.relative_tolerance);
    visit("absolute_tolerance", o.absolute_tolerance);
    visit("symmetric", o.symmetric);
    visit("trim_fraction", o.trim_fraction);
    visit("max_correspondence_distance", o.max_correspondence_distance);
    // Each start is iterated on its own and the winner chosen in a fixed order (rmse, then index): the same
    // result on one thread or many.
    visit("parallel", o.parallel, kNoEffect);
    visit("progress", o.progress, kNoEffect);  // hears a stop, computes nothing
  }
};

// Why ICP cannot take `points` at any size ("" when it can): fewer than 4 points, a non-finite coordinate,
// or points that span no plane (all on one line or at one point: 1 point, copies of one point), which leave
// the rotation about the line undefined. Decided at unit size (the centred points times a power of two), so
// the answer does not depend on the units; rounding of the coordinates (a spread within about 1e-13 of their
// magnitude) counts as no spread. IcpShape throws it; drivers ask first, to name the set.
std::string icp_points_refusal(const Points& points);

// The sizes (largest distance of a point from the centroid) ICP accepts: squared distances of a million
// points summed stay within the range of a double.
inline constexpr double kIcpSmallestSize = 1e-140;
inline constexpr double kIcpLargestSize = 1e140;
// Why ICP cannot take `points` by their size ("" when it can): the largest distance from their centroid
// outside [kIcpSmallestSize, kIcpLargestSize]. IcpShape throws it; callers that align at any scale
// (aligned_shape_distance, pairwise_distances) first bring the sets to unit size by a power of two.
std::string icp_size_refusal(const Points& points);

// A point set prepared for ICP: centroid, principal axes, a KD-tree, and nested random subsamples of the
// sizes in options.pyramid (queries on the coarse levels; partners are always searched among all points).
// Build once per shape, reuse for every alignment (the all-pairs distance matrix aligns each shape n−1
// times). Immutable after construction; thread-safe.
class IcpShape {
 public:
  // points: n×3 that icp_points_refusal accepts (n ≥ 4, finite, spanning a plane), of a size within
  // [kIcpSmallestSize, kIcpLargestSize]. Uses options.pyramid and options.seed.
  explicit IcpShape(const Points& points, const IcpOptions& options = {});

  Index size() const { return points_.rows(); }
  const Points& points() const { return points_; }
  const Eigen::Vector3d& centroid() const { return centroid_; }
  // Columns: principal axes, by decreasing variance (a right-handed frame: determinant +1).
  const Eigen::Matrix3d& principal_axes() const { return axes_; }
  const Eigen::Vector3d& principal_variances() const { return variances_; }
  double rms_radius() const { return rms_radius_; }

  // Levels 0 .. num_levels()−1 = pyramid.size(): the subsamples, then all points (a pyramid size ≥ n is
  // all points too). level_points(l): the level's points, centred (centroid subtracted) and stored in a
  // spatially coherent order (Morton curve: neighbouring queries touch the same tree nodes);
  // level_indices(l)[k]: the row of points() that level row k is.
  int num_levels() const { return static_cast<int>(levels_.size()); }
  const Points& level_points(int level) const { return levels_.at(static_cast<size_t>(level))->centred; }
  const std::vector<int>& level_indices(int level) const {
    return levels_.at(static_cast<size_t>(level))->indices;
  }
  // The KD-tree of all points (centred, rows as in the last level).
  const NearestNeighbors& tree() const { return *tree_; }
  const std::vector<Index>& pyramid() const { return pyramid_; }
  uint64_t seed() const { return seed_; }

 private:
  struct Level {
    std::vector<int> indices;
    Points centred;
  };
  Points points_;
  Eigen::Vector3d centroid_;
  Eigen::Matrix3d axes_;
  Eigen::Vector3d variances_;
  double rms_radius_ = 0;
  std::vector<Index> pyramid_;
  uint64_t seed_ = 0;
  std::vector<std::shared_ptr<const Level>> levels_;  // levels at least n share the full level
  std::unique_ptr<NearestNeighbors> tree_;
};

struct IcpResult {
  RigidTransform transform;  // maps source onto target: y ≈ R·x + t
  // RMS distance of the kept pairs at the last step on all points (target units); without
  // refine_on_all_points, of all nearest-neighbour pairs of both directions under the final transform.
  double rmse = 0;
  double inlier_fraction = 1;  // fraction of pairs kept at that step (below 1 with trimming / max distance)
  int iterations = 0;        // ICP steps of the winning start on all points (0 without refine_on_all_points)
  int total_iterations = 0;  // ICP steps of every start on every level
  bool converged = false;    // stopped by a tolerance rather than max_iterations
  std::string stop_reason;   // "relative change", "exact fit" or "max iterations"
  int best_start = 0;        // index into start_transforms of the winning start
  std::vector<RigidTransform> start_transforms;  // every starting pose tried
  std::vector<double> start_rmse;                // each start's RMSE after screening (coarsest level)
  std::vector<double> rmse_history;              // RMSE per step of the winner on all points

  // Nearest neighbours under the final transform, on all points: source point i is closest to target
  // point source_to_target[i], at Euclidean (NOT squared) distance source_to_target_distance[i];
  // likewise target_to_source (computed also when symmetric is false).
  Eigen::VectorXi source_to_target;
  Eigen::VectorXd source_to_target_distance;
  Eigen::VectorXi target_to_source;
  Eigen::VectorXd target_to_source_distance;

  double seconds = 0;  // wall time
};

// Aligns source onto target. Both shapes must have been built with the same options.pyramid and seed
// (checked). Throws cshapes::Error on invalid options.
IcpResult icp(const IcpShape& source, const IcpShape& target, const IcpOptions& options = {});

// One-shot form: builds both shapes, then aligns.
IcpResult icp(const Points& source, const Points& target, const IcpOptions& options = {});

// The starting poses that icp() tries, in its order (source and target centred on their centroids first).
std::vector<RigidTransform> icp_starts(const IcpShape& source, const IcpShape& target,
                                       const IcpOptions& options);

// Options as one canonical line ("icp;try_principal_axes=1;...": options_key, support/option_fields.h) for cache
// keys: equal strings, equal results. The same text as the hand-written list it replaced.
std::string to_key_string(const IcpOptions& options);

}  // namespace cshapes
