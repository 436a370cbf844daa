#include "eval/correspondence_error.h"

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>

#include "core/error.h"
#include "core/geodesics.h"
#include "core/io.h"
#include "core/synthetic.h"
#include "matching/icp.h"
#include "tests/test_support.h"

namespace cshapes {
namespace {

// An 11×11 grid over 10 × 12: columns 1 apart, rows 1.2 apart, area 120. Vertex (i, j) is j·11 + i.
Mesh test_grid() {
  return grid(11, 11, 10.0, 12.0);
}

std::vector<int> all_vertices(Index n) {
  std::vector<int> v(static_cast<size_t>(n));
  for (size_t i = 0; i < v.size(); ++i) v[i] = static_cast<int>(i);
  return v;
}

TEST(CorrespondenceError, IdentityMapHasNoError) {
  Mesh b = test_grid();
  std::vector<int> truth = all_vertices(b.num_vertices());
  Eigen::VectorXi identity =
      Eigen::VectorXi::LinSpaced(b.num_vertices(), 0, static_cast<int>(b.num_vertices()) - 1);
  CorrespondenceErrorOptions o;
  o.max_samples = 0;
  CorrespondenceErrorResult r = correspondence_error(b, identity, truth, truth, o);
  EXPECT_EQ(r.errors.size(), 121);
  EXPECT_EQ(r.errors.maxCoeff(), 0.0);
  for (Index t = 0; t < r.fraction.size(); ++t) EXPECT_EQ(r.fraction[t], 1.0);
  EXPECT_NEAR(r.normaliser, std::sqrt(120.0), 1e-9);
}

TEST(CorrespondenceError, ShiftedMapKnownCurve) {
  // The map moves vertex (i, j) to (i + 2, j) for i ≤ 8 and keeps columns 9, 10 (no room to move): along a
  // row the shortest edge path is the 2 horizontal edges, so 99 samples err by 2/√120 = 0.18257 and 22 by 0.
  Mesh b = test_grid();
  Eigen::VectorXi map(121);
  for (int j = 0; j < 11; ++j)
    for (int i = 0; i < 11; ++i) map[j * 11 + i] = i <= 8 ? j * 11 + i + 2 : j * 11 + i;
  std::vector<int> truth = all_vertices(121);
  CorrespondenceErrorOptions o;
  o.max_samples = 0;
  CorrespondenceErrorResult r = correspondence_error(b, map, truth, truth, o);
  const double shifted = 2.0 / std::sqrt(120.0);
  EXPECT_NEAR(r.errors.maxCoeff(), shifted, 1e-12);
  EXPECT_NEAR(r.mean_error, 99 * shifted / 121, 1e-12);
  EXPECT_NEAR(r.median_error, shifted, 1e-12);
  // Thresholds 0, 0.0025, ..., 0.25: below 0.18257 (index ≤ 73) only the 22 unmoved samples are within.
  ASSERT_EQ(r.thresholds.size(), 101);
  EXPECT_DOUBLE_EQ(r.fraction[0], 22.0 / 121);
  EXPECT_DOUBLE_EQ(r.fraction[73], 22.0 / 121);
  EXPECT_DOUBLE_EQ(r.fraction[74], 1.0);
  EXPECT_DOUBLE_EQ(r.fraction[100], 1.0);

  // Same errors from a precomputed all-pairs matrix (float: relative 1e-6), and unnormalised in B's units.
  GeodesicOptions graph;
  graph.method = GeodesicMethod::Graph;
  DistanceMatrix G = all_pairs_geodesics(b, graph);
  CorrespondenceErrorResult from_matrix = correspondence_error(b, map, truth, truth, o, &G);
  EXPECT_LT((from_matrix.errors - r.errors).cwiseAbs().maxCoeff(), 1e-6);
  o.normalise = false;
  EXPECT_NEAR(correspondence_error(b, map, truth, truth, o).errors.maxCoeff(), 2.0, 1e-12);
}

TEST(CorrespondenceError, SubsamplesEvenlyAndChecksInput) {
  Mesh b = test_grid();
  std::vector<int> truth = all_vertices(121);
  Eigen::VectorXi identity = Eigen::VectorXi::LinSpaced(121, 0, 120);
  CorrespondenceErrorOptions o;
  o.max_samples = 10;
  CorrespondenceErrorResult r = correspondence_error(b, identity, truth, truth, o);
  ASSERT_EQ(r.samples.size(), 10u);
  EXPECT_EQ(r.samples[0], 0);
  EXPECT_EQ(r.samples[1], 12);  // ⌊1·121/10⌋
  EXPECT_EQ(r.samples[9], 108);
  EXPECT_THROW(correspondence_error(b, identity.head(50), truth, truth, o), Error);  // map too short
  Eigen::VectorXi outside = identity;
  outside[0] = 500;
  EXPECT_THROW(correspondence_error(b, outside, truth, truth, o), Error);
  EXPECT_THROW(correspondence_error(b, identity, truth, {1, 2}, o), Error);
}

TEST(CorrespondenceError, ReadsVtsFiles) {
  std::string dir = test::scratch_dir("vts");
  test::write_text(dir + "/a.vts", "3\n1\n\n5 extra columns ignored\n");
  EXPECT_EQ(read_vts(dir + "/a.vts"), (std::vector<int>{2, 0, 4}));
  EXPECT_THROW(read_vts(dir + "/a.vts", 4), Error);  // index 5 > 4 vertices
  test::write_text(dir + "/zero.vts", "0\n");
  EXPECT_THROW(read_vts(dir + "/zero.vts"), Error);
  test::write_text(dir + "/text.vts", "1\nx\n");
  EXPECT_THROW(read_vts(dir + "/text.vts"), Error);
  std::filesystem::remove_all(dir);
}

TEST(CorrespondenceError, ToscaGroundTruthThroughAlignment) {
  // cat0 against a moved, mirrored copy of itself: the map ICP induces is the identity, so with cat0's
  // ground truth on both sides every sample has zero error.
  CSHAPES_REQUIRE_DATA();
  Mesh a = read_mesh(test::tosca5k("cat0"));
  std::vector<int> truth = read_vts(test::data_dir() + "/tosca5k/corres/cat0.vts", a.num_vertices());
  EXPECT_EQ(truth.size(), 5000u);
  Mesh moved = a;
  moved.V = random_rigid_transform(3, 50.0, true).apply(a.V);
  IcpResult alignment = icp(a.V, moved.V);
  CorrespondenceErrorOptions o;
  o.max_samples = 200;
  CorrespondenceErrorResult r = correspondence_error(moved, alignment.source_to_target, truth, truth, o);
  EXPECT_EQ(r.errors.maxCoeff(), 0.0);
}

}  // namespace
}  // namespace cshapes
