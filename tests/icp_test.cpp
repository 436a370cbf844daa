#include "cshapes/matching/icp.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>

#include <filesystem>
#include <nlohmann/json.hpp>
#include "cshapes/support/error.h"
#include "cshapes/mesh/io.h"
#include "cshapes/data/synthetic.h"
#include "cshapes/matching/shape_distance.h"
#include "tests/test_support.h"

namespace cshapes {
namespace icp_test {

// TOSCA cat0's 5,000 vertices when the shared data is present, else a generated 5,000-point blob.
Points test_shape() {
  if (!test::data_dir().empty()) return read_mesh(test::tosca5k("cat0")).V;
  return lumpy_blob(5000, 7);
}

Points permute_rows(const Points& X, std::vector<int>& permutation, uint64_t seed) {
  permutation.resize(static_cast<size_t>(X.rows()));
  for (size_t i = 0; i < permutation.size(); ++i) permutation[i] = static_cast<int>(i);
  std::mt19937_64 rng(seed);
  std::shuffle(permutation.begin(), permutation.end(), rng);
  Points Y(X.rows(), 3);
  for (Index i = 0; i < X.rows(); ++i) Y.row(i) = X.row(permutation[static_cast<size_t>(i)]);
  return Y;
}

double rms_radius(const Points& X) {
  return std::sqrt((X.rowwise() - X.colwise().mean()).rowwise().squaredNorm().mean());
}

// Relative error of a recovered transform: rotation in the Frobenius norm (dimensionless), translation
// relative to the shape's RMS radius; the larger of the two.
double transform_error(const RigidTransform& found, const RigidTransform& truth, double radius) {
  return std::max((found.rotation - truth.rotation).norm(),
                  (found.translation - truth.translation).norm() / radius);
}

// RigidTransform and best_rigid_transform: tests/rigid_transform_test.cpp.

TEST(IcpShape, PrincipalAxesAndLevels) {
  Points X = lumpy_blob(3000, 11);
  IcpOptions o;
  o.pyramid = {100, 1000, 5000};  // the last one exceeds n: it is the full set
  IcpShape shape(X, o);
  EXPECT_EQ(shape.num_levels(), 4);
  EXPECT_EQ(shape.level_points(0).rows(), 100);
  EXPECT_EQ(shape.level_points(1).rows(), 1000);
  EXPECT_EQ(shape.level_points(2).rows(), 3000);
  EXPECT_EQ(shape.level_points(3).rows(), 3000);
  // Nested subsamples, rows mapping back to the input.
  std::vector<int> coarse = shape.level_indices(0), fine = shape.level_indices(1);
  std::sort(coarse.begin(), coarse.end());
  std::sort(fine.begin(), fine.end());
  EXPECT_TRUE(std::includes(fine.begin(), fine.end(), coarse.begin(), coarse.end()));
  for (Index k = 0; k < 100; ++k)
    EXPECT_LT((shape.level_points(0).row(k) + shape.centroid().transpose() - X.row(shape.level_indices(0)[k]))
                  .norm(),
              1e-12);
  // The blob's longest axis is x (scaled by 3): the first principal axis is ±x.
  EXPECT_GT(std::abs(shape.principal_axes()(0, 0)), 0.95);
  EXPECT_NEAR(shape.principal_axes().determinant(), 1.0, 1e-12);
  EXPECT_GE(shape.principal_variances()[0], shape.principal_variances()[1]);
  EXPECT_GE(shape.principal_variances()[1], shape.principal_variances()[2]);
}

TEST(IcpShape, RejectsDegenerateInput) {
  EXPECT_THROW(IcpShape(Points::Zero(3, 3)), Error);
  Points line(10, 3);
  for (Index i = 0; i < 10; ++i) line.row(i) = Eigen::RowVector3d(i, 2.0 * i, -1.0 * i);
  EXPECT_THROW(IcpShape{line}, Error);
}

TEST(Icp, StartsCoverSignsAndReflections) {
  Points X = lumpy_blob(500, 12);
  IcpOptions o;
  IcpShape s(X, o);
  EXPECT_EQ(icp_starts(s, s, o).size(), 9u);  // 8 sign combinations + the identity
  o.allow_reflections = false;
  std::vector<RigidTransform> rotations = icp_starts(s, s, o);
  EXPECT_EQ(rotations.size(), 5u);
  for (const RigidTransform& T : rotations) EXPECT_FALSE(T.is_reflection());
  o.allow_reflections = true;
  o.try_axis_swaps = true;
  EXPECT_EQ(icp_starts(s, s, o).size(), 33u);
}

// The acceptance test: 100 random rigid motions (every other one a reflection) of a 5,000-point
// shape, rows shuffled, recovered to 1e-6 relative error.
TEST(Icp, RecoversRandomRigidMotionsExactly) {
  Points A = test_shape();
  const double radius = rms_radius(A);
  IcpOptions options;
  IcpShape source(A, options);
  int reflections = 0;
  for (int trial = 0; trial < 100; ++trial) {
    bool reflection = trial % 2 == 1;
    RigidTransform truth = random_rigid_transform(1000 + trial, 2 * radius, reflection);
    std::vector<int> permutation;
    Points B = permute_rows(truth.apply(A), permutation, 5000 + trial);
    IcpResult r = icp(source, IcpShape(B, options), options);
    ASSERT_LT(transform_error(r.transform, truth, radius), 1e-6) << "trial " << trial << ", rmse " << r.rmse;
    EXPECT_EQ(r.transform.is_reflection(), reflection);
    EXPECT_LT(r.rmse, 1e-6 * radius);
    reflections += r.transform.is_reflection();
    // The final correspondences are the inverse shuffle: B row k is A row permutation[k].
    if (trial == 0)
      for (Index k = 0; k < B.rows(); ++k) {
        ASSERT_EQ(r.target_to_source[k], permutation[static_cast<size_t>(k)]);
        ASSERT_EQ(r.source_to_target[permutation[static_cast<size_t>(k)]], k);
        ASSERT_LT(r.source_to_target_distance[permutation[static_cast<size_t>(k)]], 1e-6 * radius);
      }
  }
  EXPECT_EQ(reflections, 50);
}

TEST(Icp, NoReflectionsWhenForbidden) {
  Points A = lumpy_blob(2000, 13);
  const double radius = rms_radius(A);
  IcpOptions options;
  options.allow_reflections = false;
  for (int trial = 0; trial < 10; ++trial) {
    RigidTransform rotation = random_rigid_transform(300 + trial, radius, false);
    IcpResult r = icp(A, rotation.apply(A), options);
    EXPECT_LT(transform_error(r.transform, rotation, radius), 1e-6);
    // A mirror image cannot be undone by a rotation: the result stays a rotation and misfits.
    RigidTransform mirror = random_rigid_transform(400 + trial, radius, true);
    IcpResult m = icp(A, mirror.apply(A), options);
    EXPECT_FALSE(m.transform.is_reflection());
    EXPECT_GT(m.rmse, 1e-3 * radius);
  }
}

TEST(Icp, WithoutRefinementStillExactAndConsistent) {
  // Subsample queries are matched against all points, so the finest subsample alone pins an exact copy
  // down; the reported RMSE is then that of all nearest-neighbour pairs.
  Points A = lumpy_blob(3000, 21);
  const double radius = rms_radius(A);
  IcpOptions options;
  options.refine_on_all_points = false;
  for (int trial = 0; trial < 5; ++trial) {
    RigidTransform truth = random_rigid_transform(900 + trial, radius, trial % 2 == 0);
    IcpResult r = icp(A, truth.apply(A), options);
    EXPECT_LT(transform_error(r.transform, truth, radius), 1e-6);
    EXPECT_EQ(r.iterations, 0);
  }
  Points B = lumpy_blob(2500, 22);
  IcpResult r = icp(A, B, options);
  double all_pairs =
      std::sqrt((r.source_to_target_distance.squaredNorm() + r.target_to_source_distance.squaredNorm()) /
                double(A.rows() + B.rows()));
  EXPECT_NEAR(r.rmse, all_pairs, 1e-12 * radius);
}

TEST(Icp, DifferentSizesOneDirection) {
  // B: 2,000 of A's points, moved. Matched from B to all of A (one direction), every B point has its exact
  // partner, so the motion is recovered exactly although the sets differ in size.
  Points A = lumpy_blob(5000, 14);
  const double radius = rms_radius(A);
  RigidTransform truth = random_rigid_transform(15, radius, true);
  std::vector<int> permutation;
  Points B = permute_rows(truth.apply(A), permutation, 16).topRows(2000);
  IcpOptions options;
  options.symmetric = false;
  IcpResult r = icp(B, A, options);
  EXPECT_LT(transform_error(r.transform, truth.inverse(), radius), 1e-6);
  EXPECT_EQ(r.source_to_target.size(), 2000);
  EXPECT_EQ(r.target_to_source.size(), 5000);
}

// Noise of 1% of the RMS radius on every point, then also 10% of the points replaced by outliers scattered
// over the bounding box: the error stays bounded. Graceful means: with noise alone the pose error stays
// well under the noise level (1e-2; measured ~1.6e-3 — nearest-neighbour pairs of a noisy copy are not the
// true partners, so the error exceeds the least-squares rate noise/√n); outliers pull plain ICP by at most
// a few percent (measured ~2e-2); trimming 10% of the pairs brings it back under the noise level.
TEST(Icp, DegradesGracefullyWithNoiseAndOutliers) {
  Points A = test_shape();
  const double radius = rms_radius(A);
  // Converged tightly, so the errors measured are those of the noise and outliers, not of stopping early.
  IcpOptions plain;
  plain.relative_tolerance = 1e-6;
  IcpOptions trimmed = plain;
  trimmed.trim_fraction = 0.1;
  IcpShape source_plain(A, plain), source_trimmed(A, trimmed);
  std::mt19937_64 rng(17);
  std::normal_distribution<double> normal(0.0, 0.01 * radius);
  Eigen::RowVector3d lo = A.colwise().minCoeff(), hi = A.colwise().maxCoeff();
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  double worst_noise = 0, worst_plain = 0, worst_trimmed = 0;
  for (int trial = 0; trial < 5; ++trial) {
    RigidTransform truth = random_rigid_transform(600 + trial, radius, trial % 2 == 1);
    std::vector<int> permutation;
    Points noisy = A;
    for (Index i = 0; i < noisy.rows(); ++i)
      for (int c = 0; c < 3; ++c) noisy(i, c) += normal(rng);
    Points B = permute_rows(truth.apply(noisy), permutation, 700 + trial);
    worst_noise = std::max(
        worst_noise, transform_error(icp(source_plain, IcpShape(B, plain), plain).transform, truth, radius));

    Points outlying = noisy;
    for (Index i = 0; i < outlying.rows(); i += 10)
      for (int c = 0; c < 3; ++c) outlying(i, c) = lo[c] + unit(rng) * (hi[c] - lo[c]);
    Points C = permute_rows(truth.apply(outlying), permutation, 800 + trial);
    worst_plain = std::max(
        worst_plain, transform_error(icp(source_plain, IcpShape(C, plain), plain).transform, truth, radius));
    worst_trimmed = std::max(
        worst_trimmed,
        transform_error(icp(source_trimmed, IcpShape(C, trimmed), trimmed).transform, truth, radius));
  }
  EXPECT_LT(worst_noise, 0.5e-2);
  EXPECT_LT(worst_plain, 5e-2);
  EXPECT_LT(worst_trimmed, 0.5e-2);
  RecordProperty("worst_noise", std::to_string(worst_noise));
  RecordProperty("worst_outliers_plain", std::to_string(worst_plain));
  RecordProperty("worst_outliers_trimmed", std::to_string(worst_trimmed));
  std::printf("worst relative error: noise %.2e, outliers plain %.2e, trimmed %.2e\n", worst_noise,
              worst_plain, worst_trimmed);
}

TEST(Icp, RejectsBadOptions) {
  Points A = lumpy_blob(100, 18);
  IcpOptions o;
  o.trim_fraction = 0.95;
  EXPECT_THROW(icp(A, A, o), Error);
  o = {};
  o.try_principal_axes = false;
  o.try_identity = false;
  EXPECT_THROW(icp(A, A, o), Error);
  o = {};
  IcpOptions other;
  other.seed = 2;
  EXPECT_THROW(icp(IcpShape(A, o), IcpShape(A, other), o), Error);  // shapes built with other subsamples
}

TEST(Icp, KeyStringDistinguishesOptions) {
  IcpOptions a, b;
  b.trim_fraction = 0.1;
  EXPECT_NE(to_key_string(a), to_key_string(b));
  EXPECT_EQ(to_key_string(a), to_key_string(IcpOptions{}));
}

TEST(AlignCli, RecoversAMirroredCopy) {
  std::string dir = test::scratch_dir("align");
  Mesh a{lumpy_blob(800, 19), Faces(0, 3)};
  Mesh b{random_rigid_transform(20, 3.0, true).apply(a.V), Faces(0, 3)};
  write_mesh(dir + "/a.off", a);
  write_mesh(dir + "/b.off", b);
  test::CliResult r =
      test::run_cli("align '" + dir + "/a.off' '" + dir + "/b.off' --json -o '" + dir + "/moved.off'");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  nlohmann::json j = nlohmann::json::parse(r.out);
  EXPECT_TRUE(j["reflection"].get<bool>());
  EXPECT_LT(j["hausdorff"].get<double>(), 1e-6);
  EXPECT_EQ(j["transform"].size(), 4u);
  EXPECT_LT(shape_distance(read_mesh(dir + "/moved.off").V, b.V).hausdorff, 1e-5);
  // Rotations only: the mirror image cannot be undone.
  r = test::run_cli("align '" + dir + "/a.off' '" + dir + "/b.off' --json --no-reflections");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  j = nlohmann::json::parse(r.out);
  EXPECT_FALSE(j["reflection"].get<bool>());
  EXPECT_GT(j["hausdorff"].get<double>(), 1e-3);
  // Every distance also in % of B's bounding-box diagonal.
  const double diagonal = bbox_diagonal(b.V);
  EXPECT_NEAR(j["target_bbox_diagonal"].get<double>(), diagonal, 1e-9 * diagonal);
  for (const char* d : {"hausdorff", "chamfer", "rmse"})
    EXPECT_NEAR(j[std::string(d) + "_percent"].get<double>(), 100 * j[d].get<double>() / diagonal, 1e-9) << d;
  r = test::run_cli("align '" + dir + "/a.off' '" + dir + "/b.off' --no-reflections");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.out.find("% of B's bounding-box diagonal"), std::string::npos) << r.out;
  std::filesystem::remove_all(dir);
}

}  // namespace icp_test
}  // namespace cshapes
