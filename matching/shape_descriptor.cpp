#include "cshapes/matching/shape_descriptor.h"

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>

#include "cshapes/support/deterministic_random.h"
#include "cshapes/support/error.h"

namespace cshapes {

ShapeDescriptor shape_descriptor(const Points& points, const ShapeDescriptorOptions& options) {
  const Index n = points.rows();
  CSHAPES_REQUIRE(n >= 2, "shape descriptor: ", n, " points, need at least 2");
  CSHAPES_REQUIRE(points.allFinite(),
                  "shape descriptor: non-finite coordinates (drop them with finite_rows)");
  CSHAPES_REQUIRE(options.samples >= 1 && options.d2_bins >= 1 && options.d2_range > 0,
                  "shape descriptor: samples ", options.samples, ", bins ", options.d2_bins, ", range ",
                  options.d2_range);
  const Eigen::RowVector3d centroid = points.colwise().mean();
  const Points centred = points.rowwise() - centroid;
  const Eigen::Matrix3d covariance = centred.transpose() * centred / static_cast<double>(n);
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eigen(covariance);
  ShapeDescriptor d;
  for (int k = 0; k < 3; ++k)
    d.moments[k] = std::sqrt(std::max(0.0, eigen.eigenvalues()[2 - k]));  // decreasing

  const double rms_radius = std::sqrt(centred.rowwise().squaredNorm().mean());
  d.d2 = Eigen::VectorXd::Zero(options.d2_bins);
  DeterministicRandom random(options.seed);
  const double bins_per_radius = options.d2_bins / options.d2_range;
  for (int s = 0; s < options.samples; ++s) {
    const Index a = static_cast<Index>(random.index(static_cast<uint64_t>(n)));
    Index b = static_cast<Index>(random.index(static_cast<uint64_t>(n - 1)));
    if (b >= a) ++b;  // a pair of distinct points
    const double r = rms_radius > 0 ? (points.row(a) - points.row(b)).norm() / rms_radius : 0.0;
    const int bin = std::min(options.d2_bins - 1, static_cast<int>(r * bins_per_radius));
    d.d2[bin] += 1;
  }
  d.d2 /= static_cast<double>(options.samples);
  return d;
}

double descriptor_distance(const ShapeDescriptor& a, const ShapeDescriptor& b) {
  CSHAPES_REQUIRE(a.d2.size() == b.d2.size(), "descriptor distance: ", a.d2.size(), " and ", b.d2.size(),
                  " histogram bins");
  double moments = 0;
  for (int k = 0; k < 3; ++k) {
    const double sum = a.moments[k] + b.moments[k];
    if (sum > 0) moments += std::abs(a.moments[k] - b.moments[k]) / sum;
  }
  return moments / 3 + 0.5 * (a.d2 - b.d2).cwiseAbs().sum();
}

}  // namespace cshapes
