#include "cshapes/eval/correspondence_error.h"

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <limits>

#include "cshapes/support/error.h"
#include "cshapes/geodesics/geodesics.h"
#include "cshapes/mesh/io.h"
#include "cshapes/data/synthetic.h"
#include "cshapes/matching/icp.h"
#include "tests/test_support.h"

namespace cshapes {
namespace correspondence_error_test {

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

TEST(CorrespondencePairs, ReadsShrecFiles) {
  std::string dir = test::scratch_dir("pairs");
  // SHREC'16's layout: right-aligned columns, a trailing space; blank lines skipped; not every vertex listed.
  test::write_text(dir + "/good.txt", "     1      3 \n     2      2 \n\n     4  10 \n");
  CorrespondencePairs p = read_correspondence_pairs(dir + "/good.txt", 4, 10);
  EXPECT_EQ(p.from, (std::vector<int>{0, 1, 3}));
  EXPECT_EQ(p.to, (std::vector<int>{2, 1, 9}));
  std::filesystem::remove_all(dir);
}

TEST(CorrespondencePairs, ErrorsNameFileAndLine) {
  std::string dir = test::scratch_dir("pairs_bad");
  struct Case {
    std::string text, expected;
  };
  const std::vector<Case> cases = {
      {"1 3\n2\n", ":2: expected two 1-based vertex indices, got 1 field ('2')"},
      {"1 3\n2 3 4\n", ":2: expected two 1-based vertex indices, got 3 fields ('2 3 4')"},
      {"1 3\n\n2 x\n", ":3: 'x' is not a vertex index"},
      {"1 3.5\n", ":1: '3.5' is not a vertex index"},
      {"0 3\n", ":1: vertex index 0 (expected 1-based, >= 1)"},
      {"1 3\n6 1\n", ":2: vertex index 6 exceeds the query mesh's 5 vertices"},
      {"1 11\n", ":1: vertex index 11 exceeds the reference mesh's 10 vertices"},
      {"1 3\n2 4\n1 5\n", ":3: vertex 1 is listed again (first on line 1)"},
      {"\n\n", ": no vertex pair"},
  };
  for (size_t k = 0; k < cases.size(); ++k) {
    const std::string path = dir + "/bad" + std::to_string(k) + ".txt";
    test::write_text(path, cases[k].text);
    const std::string message = test::error_of([&] { read_correspondence_pairs(path, 5, 10); });
    EXPECT_EQ(message, path + cases[k].expected) << "case " << k;
  }
  const std::string missing = test::error_of([&] { read_correspondence_pairs(dir + "/none.txt"); });
  EXPECT_NE(missing.find(dir + "/none.txt"), std::string::npos) << missing;
  std::filesystem::remove_all(dir);
}

// The mirror of the test grid: (i, j) -> (10 − i, j).
int mirrored(int v) {
  return (v / 11) * 11 + 10 - v % 11;
}

TEST(SymmetricCorrespondenceError, AgreesWithOneMapScoringWithoutSymmetry) {
  // Graph geodesics on the grid: the shifted map's errors are known exactly (2/√120 or 0), and several maps
  // scored together equal each scored alone by correspondence_error.
  Mesh b = test_grid();
  std::vector<int> truth = all_vertices(121);
  Eigen::VectorXi identity = Eigen::VectorXi::LinSpaced(121, 0, 120), shifted(121);
  for (int v = 0; v < 121; ++v) shifted[v] = v % 11 <= 8 ? v + 2 : v;
  CorrespondenceErrorOptions o;
  o.max_samples = 0;
  SymmetricCorrespondenceErrorResult r =
      symmetric_correspondence_errors(b, {identity, shifted}, truth, truth, {}, o);
  ASSERT_EQ(r.maps.size(), 2u);
  EXPECT_EQ(r.maps[0].errors.maxCoeff(), 0.0);
  CorrespondenceErrorResult one = correspondence_error(b, shifted, truth, truth, o);
  EXPECT_NEAR((r.maps[1].errors - one.errors).cwiseAbs().maxCoeff(), 0.0, 1e-12);
  EXPECT_NEAR(r.maps[1].mean_error, 99 * 2.0 / std::sqrt(120.0) / 121, 1e-12);
  EXPECT_NEAR((r.maps[1].fraction - one.fraction).cwiseAbs().maxCoeff(), 0.0, 1e-12);
  EXPECT_EQ(r.symmetric_chosen, (std::vector<int>{0, 0}));
  EXPECT_EQ(r.unmapped, (std::vector<int>{0, 0}));
  EXPECT_EQ(r.skipped_samples, 0);
  EXPECT_EQ(r.repair_text, "");
}

TEST(SymmetricCorrespondenceError, ForgivesTheMirroredMapAndCountsUnmapped) {
  // A map that mirrors left and right is wrong by up to 10/√120 against the truth and exactly right against
  // the mirrored truth, which it is then scored by; fast marching (the experiment's scoring) gives 0 there
  // too.
  Mesh b = test_grid();
  std::vector<int> truth = all_vertices(121), mirror(121);
  Eigen::VectorXi flip(121);
  for (int v = 0; v < 121; ++v) flip[v] = mirror[static_cast<size_t>(v)] = mirrored(v);
  CorrespondenceErrorOptions o;
  o.max_samples = 0;
  o.geodesics.method = GeodesicMethod::FastMarching;
  SymmetricCorrespondenceErrorResult r = symmetric_correspondence_errors(b, {flip}, truth, truth, mirror, o);
  EXPECT_EQ(r.maps[0].errors.maxCoeff(), 0.0);
  EXPECT_EQ(r.symmetric_chosen[0], 110);  // all but the middle column (its mirror is itself: no gain)
  // Whole-map scoring: against the mirrored truth the flip is exact, against the truth it is not.
  ASSERT_EQ(r.mirrored_errors.size(), 1u);
  EXPECT_EQ(r.mirrored_errors[0].maxCoeff(), 0.0);
  EXPECT_GT(r.direct_errors[0].maxCoeff(), 0.8);  // 10/√120 = 0.91 at the grid's sides
  // Graph geodesics (exact along a row): without a mirrored truth the flip is up to 10/√120 wrong.
  o.geodesics.method = GeodesicMethod::Graph;
  o.max_threshold = 1.0;  // beyond every error of a mapped vertex (10/√120 = 0.91)
  SymmetricCorrespondenceErrorResult plain = symmetric_correspondence_errors(b, {flip}, truth, truth, {}, o);
  EXPECT_NEAR(plain.maps[0].errors.maxCoeff(), 10.0 / std::sqrt(120.0), 1e-12);
  // Only a few vertices have a mirrored truth (−1 elsewhere); one vertex has no image.
  std::vector<int> some(121, -1);
  some[0] = mirrored(0);
  Eigen::VectorXi partial = flip;
  partial[5] = -1;
  r = symmetric_correspondence_errors(b, {partial}, truth, truth, some, o);
  EXPECT_EQ(r.maps[0].errors[0], 0.0);
  EXPECT_NEAR(r.maps[0].errors[1], 8.0 / std::sqrt(120.0), 1e-12);  // (1, 0) -> (9, 0), no mirror given
  EXPECT_TRUE(std::isinf(r.maps[0].errors[5]));
  EXPECT_EQ(r.unmapped[0], 1);
  EXPECT_EQ(r.maps[0].fraction[r.maps[0].fraction.size() - 1], 120.0 / 121);  // never within a threshold
  EXPECT_TRUE(std::isfinite(r.maps[0].mean_error));                           // mean over mapped samples
  // Without a mirrored truth the mirrored errors fall back to the direct ones.
  EXPECT_EQ(r.mirrored_errors[0][0], 0.0);
  EXPECT_EQ(r.mirrored_errors[0][1], r.direct_errors[0][1]);
  EXPECT_TRUE(std::isinf(r.mirrored_errors[0][5]));
  EXPECT_THROW(symmetric_correspondence_errors(b, {flip}, truth, truth, {1, 2}, o), Error);
  EXPECT_THROW(symmetric_correspondence_errors(b, {flip.head(10)}, truth, truth, mirror, o), Error);
}

TEST(SymmetricCorrespondenceError, RepairsTheReferenceAndCountsItsAreaOnce) {
  // A duplicated face (as kid00.off has beside its non-manifold edge) is dropped for the geodesics: said in
  // repair_text, and √area stays √120.
  Mesh b = test_grid();
  b.F.conservativeResize(b.F.rows() + 1, 3);
  b.F.row(b.F.rows() - 1) = b.F.row(0);
  std::vector<int> truth = all_vertices(121);
  Eigen::VectorXi identity = Eigen::VectorXi::LinSpaced(121, 0, 120);
  CorrespondenceErrorOptions o;
  o.geodesics.method = GeodesicMethod::FastMarching;
  SymmetricCorrespondenceErrorResult r =
      symmetric_correspondence_errors(b, {identity}, truth, truth, {}, o, "b.off");
  EXPECT_NE(r.repair_text.find("b.off"), std::string::npos) << r.repair_text;
  EXPECT_NEAR(r.maps[0].normaliser, std::sqrt(120.0), 1e-9);
  EXPECT_EQ(r.maps[0].errors.maxCoeff(), 0.0);
}

TEST(CorrespondenceError, ErrorStatisticsKnownAnswers) {
  const double inf = std::numeric_limits<double>::infinity();
  // Unmapped samples (+inf) count in the median and the fractions, not in the mean.
  Eigen::VectorXd e(5);
  e << 0.3, inf, 0.1, 0.2, inf;
  EXPECT_DOUBLE_EQ(finite_mean(e), 0.2);
  EXPECT_EQ(error_median(e), 0.3);  // odd count: the middle of 0.1 0.2 0.3 inf inf
  EXPECT_DOUBLE_EQ(fraction_within(e, 0.2), 0.4);
  EXPECT_DOUBLE_EQ(fraction_within(e, 10.0), 0.6);
  // Even count: the mean of the two middle values (support/timing.h's median of repeats takes the upper one).
  Eigen::VectorXd even(4);
  even << 0.4, 0.1, 0.2, 0.3;
  EXPECT_DOUBLE_EQ(error_median(even), 0.25);
  EXPECT_DOUBLE_EQ(error_median(Eigen::Vector4d(inf, 0.2, 0.4, 0.1)), 0.5 * (0.2 + 0.4));
  EXPECT_EQ(error_median(Eigen::Vector4d(0.1, inf, 0.2, inf)), inf);  // half the samples unmapped
  // Empty, or nothing mapped.
  EXPECT_TRUE(std::isnan(finite_mean(Eigen::VectorXd())));
  EXPECT_TRUE(std::isnan(error_median(Eigen::VectorXd())));
  EXPECT_EQ(fraction_within(Eigen::VectorXd(), 1.0), 0.0);
  EXPECT_TRUE(std::isnan(finite_mean(Eigen::VectorXd::Constant(3, inf))));
}

}  // namespace correspondence_error_test
}  // namespace cshapes
