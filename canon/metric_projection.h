// Projection onto the metric constraints of §2.1–2.2: pulling edge lengths ‖x_i − x_j‖ back towards their
// rest lengths d_ij, one Jacobi sweep at a time, on an arbitrary edge graph (mesh edges or a kNN graph).
//
//   L2 (eq. 6, Groginsky):  x_i ← (1/v_i) Σ_{j~i} ( x_j + t_ij (x_i − x_j)/‖x_i − x_j‖ )
//   L1 (eq. 8–9):           x_i ← Σ_{j~i} w_ij ( x_j + t_ij (x_i − x_j)/‖x_i − x_j‖ ),
//                           w_ij ∝ 1 / max(|‖x_i − x_j‖ − d_ij|, floor · d_ij), normalised over the edges of
//                           i
//
// v_i is the degree of vertex i (the paper assumes it constant; we use each vertex's own). The target t_ij is
// d_ij (eq. 2's equality constraints) or, with dilation c > 1, the length clamped into [d_ij/c, c·d_ij]
// (eq. 3's band: edges inside it exert no pull). All vertices are updated from the previous sweep's positions
// (Jacobi), so the result does not depend on the thread count.
//
// Monotonicity: an L2 sweep never increases the residual of eq. (5) (with t in place of d). It minimises,
// vertex by vertex, SMACOF's majoriser of eq. (5), and the Jacobi update of that quadratic cannot increase it
// because the graph Laplacian is bounded by twice its degree matrix. The L1 sweep is the same step for the
// reweighted residual (iteratively reweighted least squares) and carries no such guarantee for eq. (5).
//
// Known limitation (measured: docs/results.md): the averaged projection barely pulls back a uniformly dilated
// smooth surface — the pulls of opposite neighbours cancel — so after Coulomb steps the violation never
// returns to 0.
//
// Coincident endpoints (‖x_i − x_j‖ below 1e-12 · d_ij) get a fixed direction (±e_x, opposite for i and j)
// so they separate instead of producing NaN.
//
// Complexity: O(|E|) per sweep, OpenMP over edges and vertices (from 2,000 vertices).
#pragma once

#include "cshapes/support/aligned_allocator.h"
#include "cshapes/support/option_limits.h"

#include <string>
#include <vector>

#include <Eigen/Core>

#include "cshapes/mesh/mesh.h"
#include "cshapes/support/option_fields.h"

namespace cshapes {

enum class ProjectionNorm {
  L2,  // eq. (6): plain average of the projections on the spheres around the neighbours
  L1   // eq. (8)-(9): weighted by the inverse violation, so strongly stretched edges give way
};
ProjectionNorm parse_projection_norm(const std::string& name);  // "l2" | "l1"
std::string to_string(ProjectionNorm norm);

// The limits of the options a user sets (support/option_limits.h), named as on the command line.
namespace projection_limits {
inline constexpr Limit kSteps = integer_limit("projection-steps", 0, 1e6);
inline constexpr Limit kL1Floor = number_limit("l1-floor", 0, kNoLimit, /*minimum_open=*/true);
inline constexpr Limit kDilation = number_limit("dilation", 1);
}  // namespace projection_limits

struct MetricProjectionOptions {
  ProjectionNorm norm =
      ProjectionNorm::L2;  // L2: the paper's default scheme; L1 for topological noise (§2.2)
  int steps = 10;          // k: Jacobi sweeps per call of project() (measured: docs/coulomb-defaults.md)
  // L1 only: |r_ij − d_ij| is floored at l1_floor · d_ij before inverting. The paper's absolute 1e-16 lets
  // one barely-violated edge take all the weight of its vertex, which made the projection weaker (measured in
  // the prototype); a relative floor makes edges violated by less than it count equally (a Huber-like norm).
  double l1_floor = 0.05;
  // Dilation constant c ≥ 1 of eq. (3): 1 pulls every edge to d_ij; c > 1 pulls only edges outside
  // [d_ij/c, c·d_ij] to the nearer bound.
  double dilation = 1.0;

  // Every field by name, for cache keys (support/option_fields.h). Self: MetricProjectionOptions, const or not.
  template <class Self, class Visit>
  static void for_each_field(Self& o, Visit&& visit) {
    visit("norm", o.norm);
    visit("steps", o.steps);
    visit("l1_floor", o.l1_floor);
    visit("dilation", o.dilation);
  }
};

// The mean and max of |r_ij − d_ij| / d_ij: what the Coulomb iteration records after every projection.
struct RelativeViolation {
  double mean = 0;
  double max = 0;
};

// A reusable projector for a fixed graph (set-up: O(|E| log |E|) to orient and sort the edges).
//
// A sweep runs in two vectorised passes (OpenMP-parallel from 2,000 vertices): (1) per edge (a, b), with
// v = t_ab (x_a − x_b) / ‖x_a − x_b‖, the projections of both endpoints, x_b + v for a and x_a − v for b,
// times their weight, written to a slot of each endpoint: each square root and division is done once per
// edge, not once per endpoint; (2) per vertex, the sum over its slots, which lie contiguously, divided by Σ
// w_ij. The vertices are renumbered internally in breadth-first order (memory locality); every vertex's sum
// is formed in a fixed order (its neighbours by that numbering), so the result is bit-identical for identical
// inputs and does not depend on the number of threads. Per sweep at 5,000 vertices (one thread): ≈ 0.05
// ms, 2.7× faster than a single pass over the adjacency (which computes each edge once per endpoint).
class MetricProjection {
 public:
  // n vertices; E |E|×2 edges (0-based, either orientation); rest_lengths |E| values d_ij ≥ 0 (zeros are
  // raised to 1e-12 × the largest, so relative quantities stay finite).
  MetricProjection(Index num_vertices, const Edges& E, const Eigen::VectorXd& rest_lengths,
                   const MetricProjectionOptions& options = {});

  // One Jacobi sweep, in place. Isolated vertices do not move. X: n×3.
  void sweep(Points& X) const;
  // options.steps sweeps. If `violation` is given, it receives the relative violation of the result (as
  // relative_violation(X) afterwards would give it, up to rounding), measured inside the same parallel pass.
  void project(Points& X, RelativeViolation* violation = nullptr) const;

  // The relative violation of X over this graph's edges (rest lengths as raised above). O(|E|), OpenMP with
  // a reduction in a fixed order (deterministic), no allocation: cheap enough for every iteration, unlike
  // metric_violation's median.
  RelativeViolation relative_violation(const Points& X) const;

  Index num_vertices() const { return n_; }
  Index num_edges() const { return static_cast<Index>(edge_a_.size()); }
  const MetricProjectionOptions& options() const { return options_; }

 private:
  void sweeps(Points& X, int count, RelativeViolation* violation) const;
  RelativeViolation combine_violation_blocks() const;
  template <bool L1, bool Dilation>
  void edge_pass(const double* positions, Index first, Index last) const;
  template <bool L1>
  void vertex_pass(const double* positions, double* out, Index first, Index last) const;

  Index n_;
  MetricProjectionOptions options_;
  // order_[i]: the input index of internal vertex i (breadth-first order, for memory locality).
  std::vector<int> order_;
  // The edges in internal indices, oriented a < b and sorted by (a, b); their rest lengths.
  std::vector<int> edge_a_, edge_b_;
  std::vector<double> edge_rest_;
  // Vertex i's slots are [offsets_[i], offsets_[i+1]), one per edge, by increasing neighbour index; edge e
  // writes its endpoints' projections into slots slot_a_[e] and slot_b_[e].
  std::vector<int> offsets_, slot_a_, slot_b_;
  std::vector<double> inverse_degree_;  // 1 / v_i (0 for an isolated vertex)
  // Work space: positions as 4-double records (x, y, z, 1) for two Jacobi buffers, and a record
  // (w·p_x, w·p_y, w·p_z, w) per slot (2|E|).
  using AlignedDoubles = std::vector<double, AlignedAllocator<double>>;  // the kernels' aligned loads
  mutable AlignedDoubles positions_a_, positions_b_, slots_;
  mutable std::vector<double> block_sums_, block_maxima_;  // the violation's partial results per edge block
};

// How far X is from the rest lengths, over the edges E.
struct MetricViolation {
  double residual = 0;             // eq. (5): Σ (d_ij − r_ij)²
  double l1 = 0;                   // eq. (7): Σ |d_ij − r_ij|
  double mean_relative = 0;        // mean of |r_ij − d_ij| / d_ij
  double max_relative = 0;         // max of |r_ij − d_ij| / d_ij
  double median_length_ratio = 0;  // median of r_ij / d_ij (1 when lengths are kept; > 1 when inflated)
};
MetricViolation metric_violation(const Points& X, const Edges& E, const Eigen::VectorXd& rest_lengths);

}  // namespace cshapes
