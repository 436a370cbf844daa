#include "cshapes/matching/shape_distance.h"

#include <gtest/gtest.h>

#include <cmath>
#include <initializer_list>
#include <random>
#include <string>
#include <utility>
#include <vector>

#include "cshapes/support/error.h"

namespace cshapes {
namespace shape_distance_test {

Points random_points(Index n, uint64_t seed, double sx = 3, double sy = 1.5, double sz = 1) {
  std::mt19937_64 rng(seed);
  std::normal_distribution<double> normal(0.0, 1.0);
  Points X(n, 3);
  for (Index i = 0; i < n; ++i)
    X.row(i) = Eigen::RowVector3d(sx * normal(rng), sy * normal(rng), sz * normal(rng));
  return X;
}

// Brute force over all pairs: the definitions in shape_distance.h, written out.
ShapeDistance brute_force(const Points& A, const Points& B) {
  Eigen::VectorXd ab(A.rows()), ba(B.rows());
  for (Index i = 0; i < A.rows(); ++i)
    ab[i] = std::sqrt((B.rowwise() - A.row(i)).rowwise().squaredNorm().minCoeff());
  for (Index j = 0; j < B.rows(); ++j)
    ba[j] = std::sqrt((A.rowwise() - B.row(j)).rowwise().squaredNorm().minCoeff());
  ShapeDistance d;
  d.directed_ab = ab.maxCoeff();
  d.directed_ba = ba.maxCoeff();
  d.hausdorff = std::max(d.directed_ab, d.directed_ba);
  d.chamfer = 0.5 * (ab.mean() + ba.mean());
  d.rmse = std::sqrt((ab.squaredNorm() + ba.squaredNorm()) / double(A.rows() + B.rows()));
  return d;
}

TEST(ShapeDistance, KnownAnswer) {
  // A = {0, e_x}, B = {0, 3 e_x, 3 e_x + e_y}... on a line and a corner, by hand:
  //   d_A: 0 → 0 (to 0), e_x → 1 (to 0)                     max 1, mean 0.5
  //   d_B: 0 → 0, 3e_x → 2 (to e_x), 3e_x+e_y → √5 (to e_x)  max √5, mean (2 + √5)/3
  Points A(2, 3), B(3, 3);
  A << 0, 0, 0, 1, 0, 0;
  B << 0, 0, 0, 3, 0, 0, 3, 1, 0;
  ShapeDistance d = shape_distance(A, B);
  EXPECT_DOUBLE_EQ(d.directed_ab, 1.0);
  EXPECT_DOUBLE_EQ(d.directed_ba, std::sqrt(5.0));
  EXPECT_DOUBLE_EQ(d.hausdorff, std::sqrt(5.0));
  EXPECT_DOUBLE_EQ(d.chamfer, 0.5 * (0.5 + (2 + std::sqrt(5.0)) / 3));
  EXPECT_DOUBLE_EQ(d.rmse, std::sqrt((0 + 1 + 0 + 4 + 5) / 5.0));
}

TEST(ShapeDistance, MatchesBruteForceAndIsSymmetric) {
  Points A = random_points(400, 1), B = random_points(300, 2);
  ShapeDistance d = shape_distance(A, B), e = brute_force(A, B), r = shape_distance(B, A);
  EXPECT_NEAR(d.hausdorff, e.hausdorff, 1e-12);
  EXPECT_NEAR(d.chamfer, e.chamfer, 1e-12);
  EXPECT_NEAR(d.rmse, e.rmse, 1e-12);
  EXPECT_DOUBLE_EQ(r.hausdorff, d.hausdorff);
  EXPECT_NEAR(r.chamfer, d.chamfer, 1e-12);
  EXPECT_NEAR(r.rmse, d.rmse, 1e-12);
  EXPECT_DOUBLE_EQ(r.directed_ab, d.directed_ba);
}

TEST(ShapeDistance, ZeroOnIdenticalSets) {
  Points A = random_points(500, 3);
  ShapeDistance d = shape_distance(A, A);
  EXPECT_EQ(d.hausdorff, 0.0);
  EXPECT_EQ(d.chamfer, 0.0);
  EXPECT_EQ(d.rmse, 0.0);
  // After alignment, also for a moved, reflected, reshuffled copy: zero up to rounding.
  Points B = random_rigid_transform(4, 10.0, true).apply(A).colwise().reverse();
  ShapeDistance aligned = aligned_shape_distance(A, B);
  const double scale = std::sqrt(A.rowwise().squaredNorm().mean());
  EXPECT_LT(aligned.hausdorff, 1e-9 * scale);
  EXPECT_LT(aligned.chamfer, 1e-9 * scale);
}

TEST(ShapeDistance, AlignedDistanceIsInvariantToRigidMotionAndSymmetric) {
  // Two different shapes: the aligned distance must not depend on where either is placed, and ICP
  // from A to B and from B to A reach the same optimum (symmetric matching, same starts up to inversion).
  Points A = random_points(1500, 5), B = random_points(1200, 6, 2.5, 1.8, 1.1);
  IcpOptions o;
  o.relative_tolerance = 1e-9;
  IcpResult alignment;
  ShapeDistance d = aligned_shape_distance(A, B, o, &alignment);
  const double scale = d.chamfer;
  for (int trial = 0; trial < 3; ++trial) {
    Points A2 = random_rigid_transform(10 + trial, 5.0, trial == 1).apply(A);
    Points B2 = random_rigid_transform(20 + trial, 5.0, trial == 2).apply(B);
    ShapeDistance moved = aligned_shape_distance(A2, B2, o);
    EXPECT_NEAR(moved.chamfer, d.chamfer, 1e-3 * scale) << trial;
    EXPECT_NEAR(moved.rmse, d.rmse, 1e-3 * scale) << trial;
    EXPECT_NEAR(moved.hausdorff, d.hausdorff, 2e-2 * d.hausdorff) << trial;
  }
  ShapeDistance back = aligned_shape_distance(B, A, o);
  EXPECT_NEAR(back.chamfer, d.chamfer, 1e-3 * scale);
  EXPECT_NEAR(back.rmse, d.rmse, 1e-3 * scale);
  // The distance from the ICP result equals measuring the moved source against the target directly.
  ShapeDistance direct = shape_distance(alignment.transform.apply(A), B);
  EXPECT_NEAR(direct.hausdorff, d.hausdorff, 1e-9 * scale);
  EXPECT_NEAR(direct.chamfer, d.chamfer, 1e-9 * scale);
  EXPECT_NEAR(direct.rmse, d.rmse, 1e-9 * scale);
}

// Invariant: the aligned distance scales with the sets, at any finite scale. ICP's squared distances leave
// the double range beyond 1e±140; `cshapes align` of two shapes of 1e300 refused them as "points on a line".
// A prepared IcpShape refuses such a set by its size (so that a dataset names the shape).
TEST(ShapeDistance, AlignedDistanceScalesWithTheSetsAtAnyFiniteScale) {
  const Points A = random_points(600, 5), B = random_rigid_transform(3, 5.0, false).apply(random_points(500, 6));
  IcpOptions o;
  IcpResult unit_alignment;
  const ShapeDistance unit = aligned_shape_distance(A, B, o, &unit_alignment);
  for (double s : {1e-300, 1e-200, 1e-150, 1e150, 1e200, 1e300}) {
    SCOPED_TRACE(s);
    IcpResult r;
    const ShapeDistance d = aligned_shape_distance(A * s, B * s, o, &r);
    EXPECT_NEAR(d.hausdorff / s, unit.hausdorff, 1e-9 * unit.hausdorff);
    EXPECT_NEAR(d.chamfer / s, unit.chamfer, 1e-9 * unit.chamfer);
    EXPECT_NEAR(d.rmse / s, unit.rmse, 1e-9 * unit.rmse);
    EXPECT_NEAR(r.rmse / s, unit_alignment.rmse, 1e-9 * unit_alignment.rmse);
    EXPECT_LE((r.transform.rotation - unit_alignment.transform.rotation).cwiseAbs().maxCoeff(), 1e-9);
    EXPECT_LE((r.transform.translation / s - unit_alignment.transform.translation).norm(),
              1e-9 * unit_alignment.transform.translation.norm());
    try {
      IcpShape too_far(A * s, o);
      ADD_FAILURE() << "an IcpShape of size " << s << " accepted";
    } catch (const Error& e) {
      EXPECT_NE(std::string(e.what()).find("squared distances"), std::string::npos) << e.what();
    }
  }
}

// Expects `call` to throw a cshapes::Error whose message holds every one of `parts`.
template <class Call>
void expect_error_naming(Call&& call, std::initializer_list<const char*> parts) {
  try {
    call();
    ADD_FAILURE() << "no error";
  } catch (const Error& e) {
    for (const char* part : parts) EXPECT_NE(std::string(e.what()).find(part), std::string::npos) << e.what();
  }
}

// Issue 57: a set that spans no plane (1 point, copies of one point, points on a line) ended the process
// (unbounded recursion at radius 0). It is refused by name, as source or target, at any scale.
TEST(ShapeDistance, SetsThatSpanNoPlaneAreRefusedByName) {
  const Points shape = random_points(200, 11);
  Points line(30, 3);
  for (Index i = 0; i < line.rows(); ++i) line.row(i) = Eigen::RowVector3d(1, 2, 3) + 0.1 * i * Eigen::RowVector3d(1, -1, 2);
  const std::vector<std::pair<Points, const char*>> degenerate = {
      {Points(Eigen::RowVector3d(1, 2, 3)), "at least 4 points"},
      {Eigen::RowVector3d(0.1, 0.2, 0.3).replicate(50, 1), "at one point"},
      {line, "on one line"}};
  for (const auto& [points, why] : degenerate)
    for (double s : {1.0, 1e-150, 1e150}) {
      SCOPED_TRACE(s);
      expect_error_naming([&] { aligned_shape_distance(points * s, shape); }, {"source set (A)", why});
      expect_error_naming([&] { aligned_shape_distance(shape, points * s); }, {"target set (B)", why});
      EXPECT_FALSE(icp_points_refusal(points * s).empty());
    }
  EXPECT_EQ(icp_points_refusal(shape * 1e-300), "");  // a set's own size is no reason
}

// Issue 57: a set of size 1e-150 or 1e150 aligned with one of unit size ended the process (the joint
// scaling left one of them out of ICP's sizes, and the call recursed without end). Sizes that no double
// range holds together are refused before any work, naming the set.
TEST(ShapeDistance, SetsOfIncomparableSizesAreRefusedByName) {
  const Points A = random_points(300, 12), B = random_points(300, 13);
  expect_error_naming([&] { aligned_shape_distance(A * 1e-150, B); }, {"source set (A)", "size"});
  expect_error_naming([&] { aligned_shape_distance(A * 1e150, B); }, {"target set (B)", "size"});
  // Sizes apart by less than that are aligned (1e-100 beside 1), and measured as the alignment places them.
  const Points tiny = A * 1e-100;
  IcpResult alignment;
  const ShapeDistance d = aligned_shape_distance(tiny, B, {}, &alignment);
  const ShapeDistance direct = shape_distance(alignment.transform.apply(tiny), B);
  EXPECT_NEAR(d.hausdorff, direct.hausdorff, 1e-9 * direct.hausdorff);
  EXPECT_NEAR(d.chamfer, direct.chamfer, 1e-9 * direct.chamfer);
}

TEST(ShapeDistance, RejectsEmpty) {
  EXPECT_THROW(shape_distance_from_nearest(Eigen::VectorXd(0), Eigen::VectorXd::Ones(3)), Error);
}

}  // namespace shape_distance_test
}  // namespace cshapes
