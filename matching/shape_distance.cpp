#include "cshapes/matching/shape_distance.h"

#include <algorithm>
#include <cmath>
#include <string>
#include <utility>

#include "cshapes/support/error.h"
#include "cshapes/mesh/unit_scale.h"
#include "cshapes/matching/nearest_neighbors.h"

namespace cshapes {

const std::vector<std::string>& shape_distance_kinds() {
  static const std::vector<std::string> kinds = {"hausdorff", "chamfer", "rmse"};
  return kinds;
}

std::string shape_distance_title(const std::string& kind) {
  return kind == "hausdorff" ? "Hausdorff" : kind == "chamfer" ? "Chamfer" : kind == "rmse" ? "RMSE" : kind;
}

ShapeDistance shape_distance_from_nearest(const Eigen::VectorXd& a_to_b, const Eigen::VectorXd& b_to_a) {
  CSHAPES_REQUIRE(a_to_b.size() > 0 && b_to_a.size() > 0, "shape distance: empty point set");
  ShapeDistance d;
  d.directed_ab = a_to_b.maxCoeff();
  d.directed_ba = b_to_a.maxCoeff();
  d.hausdorff = std::max(d.directed_ab, d.directed_ba);
  d.chamfer = 0.5 * (a_to_b.mean() + b_to_a.mean());
  d.rmse = std::sqrt((a_to_b.squaredNorm() + b_to_a.squaredNorm()) /
                     static_cast<double>(a_to_b.size() + b_to_a.size()));
  return d;
}

Points finite_rows(const Points& X) {
  const Eigen::Array<bool, Eigen::Dynamic, 1> finite = X.array().isFinite().rowwise().all();
  const Index kept = finite.count();
  if (kept == X.rows()) return X;
  Points out(kept, 3);
  for (Index i = 0, k = 0; i < X.rows(); ++i)
    if (finite[i]) out.row(k++) = X.row(i);
  return out;
}

ShapeDistance shape_distance(const Points& A_all, const Points& B_all) {
  const Points A = finite_rows(A_all), B = finite_rows(B_all);
  NearestNeighbors tree_a(A), tree_b(B);
  Eigen::VectorXi index;
  Eigen::VectorXd a_to_b, b_to_a;
  tree_b.nearest_all(A, index, a_to_b);
  tree_a.nearest_all(B, index, b_to_a);
  return shape_distance_from_nearest(a_to_b.cwiseSqrt(), b_to_a.cwiseSqrt());
}

ShapeDistance shape_distance(const IcpResult& alignment) {
  return shape_distance_from_nearest(alignment.source_to_target_distance,
                                     alignment.target_to_source_distance);
}

ShapeDistance aligned_shape_distance(const IcpShape& A, const IcpShape& B, const IcpOptions& options,
                                     IcpResult* alignment) {
  IcpResult r = icp(A, B, options);
  ShapeDistance d = shape_distance(r);
  if (alignment) *alignment = std::move(r);
  return d;
}

void scale_lengths(double factor, ShapeDistance& distance, IcpResult* alignment) {
  for (double* x : {&distance.hausdorff, &distance.chamfer, &distance.rmse, &distance.directed_ab,
                    &distance.directed_ba})
    *x *= factor;
  if (!alignment) return;
  IcpResult& r = *alignment;
  r.transform.translation *= factor;
  r.rmse *= factor;
  for (RigidTransform& T : r.start_transforms) T.translation *= factor;
  for (double& x : r.start_rmse) x *= factor;
  for (double& x : r.rmse_history) x *= factor;
  r.source_to_target_distance *= factor;
  r.target_to_source_distance *= factor;
}

ShapeDistance aligned_shape_distance(const Points& A, const Points& B, const IcpOptions& options,
                                     IcpResult* alignment) {
  const Points a_points = finite_rows(A), b_points = finite_rows(B);
  // A set ICP cannot take at any size is refused by name before any work.
  if (std::string refusal = icp_points_refusal(a_points); !refusal.empty()) fail("the source set (A): ", refusal);
  if (std::string refusal = icp_points_refusal(b_points); !refusal.empty()) fail("the target set (B): ", refusal);
  if (icp_size_refusal(a_points).empty() && icp_size_refusal(b_points).empty()) {
    IcpShape a(a_points, options), b(b_points, options);
    return aligned_shape_distance(a, b, options, alignment);
  }
  // Sets too small or too large for squared distances: aligned with the larger brought to unit size (a power
  // of two: exact), then measured in their own units. The bounding-box extent ignores where the sets lie, as
  // ICP does (it centres them).
  const double scale = std::min(power_of_two_unit_scale(a_points), power_of_two_unit_scale(b_points));
  const Points a_scaled = a_points * scale, b_scaled = b_points * scale;
  const auto too_small = [](const Points& points) { return !icp_size_refusal(points).empty(); };
  if (too_small(a_scaled) || too_small(b_scaled))
    fail("ICP: the ", too_small(a_scaled) ? "source set (A)" : "target set (B)", " is under ", kIcpSmallestSize,
         " times the size of the other; squared distances of both do not fit in a double: scale the sets to "
         "comparable sizes");
  IcpOptions scaled = options;
  scaled.max_correspondence_distance *= scale;  // absolute_tolerance is relative to the target's radius
  IcpShape a(a_scaled, scaled), b(b_scaled, scaled);
  ShapeDistance d = aligned_shape_distance(a, b, scaled, alignment);
  scale_lengths(1 / scale, d, alignment);
  return d;
}

}  // namespace cshapes
