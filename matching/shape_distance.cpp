#include "cshapes/matching/shape_distance.h"

#include <cmath>

#include "cshapes/support/error.h"
#include "cshapes/mesh/unit_scale.h"
#include "cshapes/matching/nearest_neighbors.h"

namespace cshapes {

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

namespace {

// An alignment computed on both sets multiplied by `scale`, in the units of the sets themselves.
void unscale(IcpResult& r, double scale) {
  r.transform.translation /= scale;
  r.rmse /= scale;
  for (RigidTransform& T : r.start_transforms) T.translation /= scale;
  for (double& x : r.start_rmse) x /= scale;
  for (double& x : r.rmse_history) x /= scale;
  r.source_to_target_distance /= scale;
  r.target_to_source_distance /= scale;
}

}  // namespace

ShapeDistance aligned_shape_distance(const Points& A, const Points& B, const IcpOptions& options,
                                     IcpResult* alignment) {
  const Points a_points = finite_rows(A), b_points = finite_rows(B);
  if (!icp_size_refusal(a_points).empty() || !icp_size_refusal(b_points).empty()) {
    // Sets too small or too large for squared distances: aligned together at unit size (a power of two:
    // exact), then measured in their own units. A shared IcpShape stays at its own size (the caller's).
    Points both(a_points.rows() + b_points.rows(), 3);
    both << a_points, b_points;
    const double scale = power_of_two_unit_scale(both);
    IcpOptions scaled = options;
    scaled.max_correspondence_distance *= scale;  // absolute_tolerance is relative to the target's radius
    IcpResult r;
    ShapeDistance d = aligned_shape_distance(a_points * scale, b_points * scale, scaled, &r);
    unscale(r, scale);
    for (double* x : {&d.hausdorff, &d.chamfer, &d.rmse, &d.directed_ab, &d.directed_ba}) *x /= scale;
    if (alignment) *alignment = std::move(r);
    return d;
  }
  IcpShape a(a_points, options), b(b_points, options);
  return aligned_shape_distance(a, b, options, alignment);
}

}  // namespace cshapes
