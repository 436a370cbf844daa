// matching/shape_descriptor.h: known answers (a box's principal deviations, a tetrahedron's single distance),
// invariance to rigid motions and reflections, the scale term, and refused input.
#include "cshapes/matching/shape_descriptor.h"

#include <gtest/gtest.h>

#include <cmath>

#include "cshapes/support/error.h"
#include "cshapes/mesh/rigid_transform.h"

namespace cshapes {
namespace shape_descriptor_test {

Points box_corners(double a, double b, double c) {
  Points X(8, 3);
  for (int k = 0; k < 8; ++k) X.row(k) << (k & 1 ? a : -a), (k & 2 ? b : -b), (k & 4 ? c : -c);
  return X;
}

// A lumpy ellipsoid of 500 points.
Points lumpy(int seed) {
  Points X(500, 3);
  for (Index i = 0; i < X.rows(); ++i) {
    const double t = 0.37 * i + seed, p = 0.11 * i;
    Eigen::Vector3d u(std::sin(p) * std::cos(t), std::sin(p) * std::sin(t), std::cos(p));
    X.row(i) = (Eigen::Vector3d(3, 1.5, 1).asDiagonal() * ((1 + 0.1 * std::sin(5 * t)) * u)).transpose();
  }
  return X;
}

TEST(ShapeDescriptor, BoxMomentsAreItsHalfSides) {
  // Corners ±(a, b, c): covariance diag(a², b², c²), whatever the order of the axes.
  const ShapeDescriptor d = shape_descriptor(box_corners(1, 3, 2));
  EXPECT_NEAR(d.moments[0], 3, 1e-12);
  EXPECT_NEAR(d.moments[1], 2, 1e-12);
  EXPECT_NEAR(d.moments[2], 1, 1e-12);
  EXPECT_NEAR(d.d2.sum(), 1, 1e-12);
}

TEST(ShapeDescriptor, TetrahedronHasOneDistance) {
  // A regular tetrahedron's vertices lie at the RMS radius r from the centroid and at r·√(8/3) from each
  // other: every sample falls in the bin of √(8/3) = 1.633 radii, bin 17 of 32 over [0, 3).
  Points X(4, 3);
  X << 1, 1, 1, 1, -1, -1, -1, 1, -1, -1, -1, 1;
  const ShapeDescriptor d = shape_descriptor(X);
  EXPECT_EQ(d.d2[17], 1.0);
  EXPECT_EQ(d.d2.sum(), 1.0);
}

TEST(ShapeDescriptor, InvariantToRigidMotionsAndReflections) {
  const Points X = lumpy(0);
  const ShapeDescriptor a = shape_descriptor(X);
  for (bool reflect : {false, true}) {
    const Points Y = random_rigid_transform(7, 5.0, reflect).apply(X);
    const ShapeDescriptor b = shape_descriptor(Y);
    EXPECT_NEAR((a.moments - b.moments).norm(), 0, 1e-12 * a.moments.norm());
    // The same pairs are measured; a distance may cross a bin edge only by rounding.
    EXPECT_LE((a.d2 - b.d2).cwiseAbs().sum(), 4.0 / ShapeDescriptorOptions{}.samples);
    EXPECT_LE(descriptor_distance(a, b), 1e-3);
  }
}

TEST(ShapeDescriptor, DistanceIsSymmetricAndSeesScaleAndShape) {
  const ShapeDescriptor a = shape_descriptor(lumpy(0)), b = shape_descriptor(box_corners(1, 2, 3));
  EXPECT_EQ(descriptor_distance(a, a), 0.0);
  EXPECT_EQ(descriptor_distance(a, b), descriptor_distance(b, a));
  EXPECT_GT(descriptor_distance(a, b), 0.1);
  // Twice the size: each moment term is |σ − 2σ| / 3σ = 1/3, the D2 histogram (in RMS radii) unchanged.
  const Points X = lumpy(0);
  const Points X2 = 2.0 * X;
  EXPECT_NEAR(descriptor_distance(a, shape_descriptor(X2)), 1.0 / 3, 1e-3);
}

TEST(ShapeDescriptor, RefusesWhatItCannotDescribe) {
  EXPECT_THROW(shape_descriptor(Points::Zero(1, 3)), Error);
  Points X = box_corners(1, 2, 3);
  X(2, 1) = std::nan("");
  EXPECT_THROW(shape_descriptor(X), Error);
  ShapeDescriptorOptions few;
  few.d2_bins = 8;
  EXPECT_THROW(descriptor_distance(shape_descriptor(box_corners(1, 2, 3)),
                                   shape_descriptor(box_corners(1, 2, 3), few)),
               Error);
}

}  // namespace shape_descriptor_test
}  // namespace cshapes
