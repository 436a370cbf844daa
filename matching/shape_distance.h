// Distances between two point sets, and the paper's shape distance: "the maximum distance between
// corresponding points after rigid alignment" (§3), correspondence meaning nearest neighbour, both ways.
//
// With d_A(a) = min_b ‖a − b‖ for a ∈ A and d_B(b) = min_a ‖a − b‖ for b ∈ B (Euclidean, NOT squared):
//   hausdorff = max( max_a d_A(a), max_b d_B(b) )                  (symmetric Hausdorff; the paper's
//   distance) chamfer   = ( mean_a d_A(a) + mean_b d_B(b) ) / 2              (mean of the two directed means)
//   rmse      = sqrt( (Σ_a d_A(a)² + Σ_b d_B(b)²) / (|A| + |B|) )  (over all pairs of both directions)
// All three are symmetric in A and B, zero when the sets are equal, in the points' units, and invariant
// under a rigid motion (or reflection) applied to both sets.
#pragma once

#include <string>
#include <vector>

#include "cshapes/support/types.h"
#include "cshapes/matching/icp.h"
#include "cshapes/support/option_declaration.h"

namespace cshapes {

// The three distances by the names options and files give them, {"hausdorff", "chamfer", "rmse"}, and each
// one's title in tables and figures ("Hausdorff", "Chamfer", "RMSE"); an unknown name is its own title.
const std::vector<std::string>& shape_distance_kinds();
// `cshapes distmat --metric` and distance_matrix(metric=) (declared once, support/option_declaration.h).
inline const OptionDeclaration kMetricOption{"metric", "--metric", "hausdorff (the paper's), chamfer or rmse",
                                             std::nullopt, shape_distance_kinds()};
std::string shape_distance_title(const std::string& kind);

struct ShapeDistance {
  double hausdorff = 0;  // the paper's distance (see above)
  double chamfer = 0;
  double rmse = 0;
  double directed_ab = 0;  // max_a d_A(a): how far A's farthest point is from B
  double directed_ba = 0;  // max_b d_B(b)
};

// The rows of X with finite coordinates, in order: canonical forms mark the vertices a repair dropped with
// NaN rows (pipeline/canonical_forms.h), and distances are measured between the points that exist. X itself when
// every row is finite.
Points finite_rows(const Points& X);

// The distances from the nearest-neighbour distances of both directions (Euclidean, not squared).
ShapeDistance shape_distance_from_nearest(const Eigen::VectorXd& a_to_b, const Eigen::VectorXd& b_to_a);

// The distances between A and B as they are placed (no alignment), over their finite rows (finite_rows).
// KD-trees: O((|A| + |B|) log).
ShapeDistance shape_distance(const Points& A, const Points& B);

// The distances after the alignment `icp` found (its final nearest neighbours; A = source, B = target).
ShapeDistance shape_distance(const IcpResult& alignment);

// Aligns A onto B with ICP, then measures: the paper's pipeline for two canonical forms. The Points overload
// uses only their finite rows (finite_rows), refuses a set ICP cannot take (icp_points_refusal: fewer than 4
// points, or all on one line or at one point), naming it ("the source set (A)"), and works at any finite
// scale: sets beyond ICP's sizes are aligned with the larger one brought to unit size by a power of two, the
// results given in their own units; it refuses sets whose sizes differ by more than a factor of about 1e140.
// The alignment is returned through `alignment` when non-null.
ShapeDistance aligned_shape_distance(const Points& A, const Points& B, const IcpOptions& options = {},
                                     IcpResult* alignment = nullptr);
ShapeDistance aligned_shape_distance(const IcpShape& A, const IcpShape& B, const IcpOptions& options = {},
                                     IcpResult* alignment = nullptr);

// Multiplies every length of a distance and of an alignment (when non-null) by `factor`: distances, RMSEs,
// translations; rotations stay. With factor 1/s, brings back to their own units the results computed on sets
// multiplied by s (exact for a power of two).
void scale_lengths(double factor, ShapeDistance& distance, IcpResult* alignment);

}  // namespace cshapes
