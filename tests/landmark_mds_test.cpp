#include "cshapes/canon/landmark_mds.h"

#include <gtest/gtest.h>

#include <random>

#include "cshapes/canon/classical_mds.h"
#include "cshapes/canon/smacof.h"
#include "cshapes/support/error.h"
#include "cshapes/geodesics/geodesics.h"
#include "cshapes/geodesics/landmark_geodesics.h"
#include "cshapes/mesh/rigid_transform.h"
#include "cshapes/data/synthetic.h"

namespace cshapes {
namespace landmark_mds_test {

double bbox_diagonal(const Points& X) {
  return (X.colwise().maxCoeff() - X.colwise().minCoeff()).norm();
}

// Normalised stress of X against the full matrix D, uniform weights: σ / Σ_{i<j} δ².
double normalized_stress(const DistanceMatrix& D, const Points& X) {
  return guttman_transform(D, X).stress / (0.5 * D.cast<double>().squaredNorm());
}

// The rows of D at the given landmarks (L × n).
Eigen::MatrixXf rows_of(const DistanceMatrix& D, const std::vector<int>& landmarks) {
  Eigen::MatrixXf rows(static_cast<Index>(landmarks.size()), D.cols());
  for (size_t k = 0; k < landmarks.size(); ++k) rows.row(static_cast<Index>(k)) = D.row(landmarks[k]);
  return rows;
}

std::vector<int> farthest_landmarks(const Mesh& m, Index count) {
  LandmarkGeodesicsOptions options;
  options.count = count;
  options.geodesics.method = GeodesicMethod::Graph;
  return landmark_geodesics(m, options).landmarks;
}

// Points of R³ and their Euclidean distances: a handful of landmarks determine every point exactly.
TEST(LandmarkMds, EuclideanDistancesAreReproducedExactly) {
  std::mt19937_64 rng(3);
  std::normal_distribution<double> normal;
  Points P(200, 3);
  for (Index i = 0; i < P.rows(); ++i) P.row(i) << 3 * normal(rng), normal(rng), 0.5 * normal(rng);
  DistanceMatrix D(P.rows(), P.rows());
  for (Index i = 0; i < P.rows(); ++i)
    for (Index j = 0; j < P.rows(); ++j) D(i, j) = static_cast<float>((P.row(i) - P.row(j)).norm());
  const std::vector<int> landmarks = {0, 17, 42, 99, 150, 7, 64, 181};
  const Eigen::MatrixXf rows = rows_of(D, landmarks);
  const double scale = bbox_diagonal(P);
  const LandmarkMdsResult classical = landmark_classical_mds(rows, landmarks);
  EXPECT_LT(aligned_rms(classical.X, P, true), 1e-5 * scale);
  const LandmarkMdsResult smacof = landmark_smacof(rows, landmarks, SmacofOptions{});
  EXPECT_LT(aligned_rms(smacof.X, P, true), 1e-4 * scale);
  EXPECT_LT(smacof.landmark_normalized_stress, 1e-9);
  EXPECT_LT(smacof.interpolated_point_stress, 1e-9);
}

// With every vertex a landmark the triangulation is the full classical MDS (up to the axes' signs).
TEST(LandmarkMds, AllVerticesAsLandmarksIsClassicalMds) {
  const Mesh m = torus(30, 12, 2.0, 0.7);
  GeodesicOptions g;
  g.method = GeodesicMethod::FastMarching;
  const DistanceMatrix D = all_pairs_geodesics(m, g);
  const std::vector<int> landmarks = farthest_landmarks(m, m.num_vertices());
  ASSERT_EQ(static_cast<Index>(landmarks.size()), m.num_vertices());
  const LandmarkMdsResult lm = landmark_classical_mds(rows_of(D, landmarks), landmarks);
  ClassicalMdsOptions dense;
  dense.dense_below = 100000;
  const ClassicalMdsResult full = classical_mds(D, dense);
  EXPECT_LT(aligned_rms(lm.X, full.X, true), 1e-5 * bbox_diagonal(full.X));
  EXPECT_NEAR(lm.eigenvalues[0], full.eigenvalues[0], 1e-6 * full.eigenvalues[0]);
  EXPECT_NEAR(lm.eigenvalues[2], full.eigenvalues[2], 1e-6 * full.eigenvalues[0]);
}

// Fewer landmarks than vertices: the form's distance to full classical MDS (after the best rigid motion or
// reflection, relative to the form's bounding-box diagonal) falls as L grows, and is small at L = n/10.
TEST(LandmarkMds, ErrorFallsAsLandmarksGrow) {
  const Mesh m = torus(64, 24, 2.0, 0.7);  // 1,536 vertices
  GeodesicOptions g;
  g.method = GeodesicMethod::FastMarching;
  const DistanceMatrix D = all_pairs_geodesics(m, g);
  const ClassicalMdsResult full = classical_mds(D);
  const double scale = bbox_diagonal(full.X);
  const std::vector<int> all = farthest_landmarks(m, 160);
  std::vector<double> errors;
  for (size_t L : {8, 20, 50, 160}) {
    const std::vector<int> landmarks(all.begin(), all.begin() + L);
    errors.push_back(aligned_rms(landmark_classical_mds(rows_of(D, landmarks), landmarks).X, full.X, true) /
                     scale);
  }
  for (size_t k = 1; k < errors.size(); ++k) EXPECT_LT(errors[k], errors[k - 1]) << "step " << k;
  EXPECT_LT(errors.back(), 0.01);
}

// SMACOF on 100 of 1,536 vertices: the landmarks' stress is at most their classical MDS start's, the
// interpolation lowers the other points' stress, and the whole form's stress against the full matrix is
// within 10% of full SMACOF's (measured: 1.3% above).
TEST(LandmarkMds, SmacofOnLandmarksStressBound) {
  const Mesh m = torus(64, 24, 2.0, 0.7);
  GeodesicOptions g;
  g.method = GeodesicMethod::FastMarching;
  const DistanceMatrix D = all_pairs_geodesics(m, g);
  const std::vector<int> landmarks = farthest_landmarks(m, 100);
  const LandmarkMdsResult lm = landmark_smacof(rows_of(D, landmarks), landmarks, SmacofOptions{});
  ASSERT_FALSE(lm.landmark_smacof.stress_history.empty());
  EXPECT_LE(lm.landmark_normalized_stress, lm.landmark_smacof.stress_history.front());
  EXPECT_LE(lm.interpolated_point_stress, lm.start_point_stress);
  const SmacofResult full = smacof(D);
  const double landmark_stress = normalized_stress(D, lm.X);
  const double full_stress = normalized_stress(D, full.X);
  EXPECT_LT(landmark_stress, 1.1 * full_stress) << "full SMACOF " << full_stress;
  // Area weights summed over Voronoi cells still give a form of the same quality.
  SmacofOptions weighted;
  weighted.vertex_weights = vertex_area_weights(m);
  const LandmarkMdsResult lw = landmark_smacof(rows_of(D, landmarks), landmarks, weighted);
  EXPECT_LT(normalized_stress(D, lw.X), 1.1 * full_stress);
}

// The fold repair on exactly embeddable rows (Euclidean distances of points of R³: each point's stress has
// one minimum). With the torus's own distances no edge is over the limit and nothing changes. Then ring 0's
// columns are made those of the opposite ring 16, so the interpolation puts ring 0 on top of ring 16, across
// the torus from its neighbours in rings 1 and 31: a fold. The repair cuts its edges, places ring 0 again
// from its neighbours (within one edge of their mean) and leaves every other point as it was.
TEST(LandmarkMds, FoldRepairPlacesAFoldedRingBackBesideItsNeighbours) {
  const int nu = 32, nv = 12;
  const Mesh m = torus(nu, nv, 2.0, 0.7);  // vertex i·nv + j: ring i
  const Index n = m.num_vertices();
  DistanceMatrix D(n, n);
  for (Index i = 0; i < n; ++i)
    for (Index j = 0; j < n; ++j) D(i, j) = static_cast<float>((m.V.row(i) - m.V.row(j)).norm());
  const std::vector<int> landmarks = {13, 40, 100, 150, 230, 300, 333, 370};  // none on ring 0
  Eigen::MatrixXf rows = rows_of(D, landmarks);
  LandmarkNeighbourGraph graph;
  graph.edges = mesh_edges(m.F);
  graph.lengths.resize(graph.edges.rows());
  for (Index e = 0; e < graph.edges.rows(); ++e)
    graph.lengths[e] = (m.V.row(graph.edges(e, 0)) - m.V.row(graph.edges(e, 1))).norm();
  const LandmarkMdsResult plain = landmark_smacof(rows, landmarks, SmacofOptions{});
  const LandmarkMdsResult kept = landmark_smacof(rows, landmarks, SmacofOptions{}, 30, {}, graph);
  EXPECT_EQ(kept.replaced_points, 0);
  EXPECT_EQ(kept.repair_rounds, 0);
  EXPECT_EQ(kept.overstretched_edges, 0);
  EXPECT_EQ(kept.X, plain.X);

  const Index opposite = (nu / 2) * nv;
  for (int j = 0; j < nv; ++j) rows.col(j) = rows.col(opposite + j);
  const LandmarkMdsResult folded = landmark_smacof(rows, landmarks, SmacofOptions{});
  const LandmarkMdsResult repaired = landmark_smacof(rows, landmarks, SmacofOptions{}, 30, {}, graph);
  const double edge = graph.lengths.mean();
  EXPECT_GT((folded.X.row(0) - folded.X.row(nv)).norm(), 10 * edge);  // the fold: ring 0 beside ring 16
  EXPECT_EQ(repaired.replaced_points, nv);
  EXPECT_EQ(repaired.repair_rounds, 1);
  EXPECT_EQ(repaired.overstretched_edges, 0);
  // Off ring 0 nothing moved (up to the centring's shift); ring 0 lies within two edges of where it belongs.
  const Points moved = repaired.X.bottomRows(n - nv) - folded.X.bottomRows(n - nv);
  EXPECT_LT((moved.rowwise() - moved.row(0)).cwiseAbs().maxCoeff(), 1e-12 * bbox_diagonal(m.V));
  const RigidTransform fit = best_rigid_transform(repaired.X.bottomRows(n - nv), m.V.bottomRows(n - nv), 0);
  EXPECT_LT((fit.apply(Points(repaired.X.bottomRows(n - nv))) - m.V.bottomRows(n - nv)).cwiseAbs().maxCoeff(),
            1e-4 * edge);
  const Points ring = fit.apply(Points(repaired.X.topRows(nv)));
  for (int j = 0; j < nv; ++j) EXPECT_LT((ring.row(j) - m.V.row(j)).norm(), 2 * edge) << "vertex " << j;
}

TEST(LandmarkMds, SolverRule) {
  MdsSolverOptions o;
  for (const char* name : {"full", "landmarks", "auto"}) EXPECT_EQ(to_string(parse_mds_solver(name)), name);
  EXPECT_THROW(parse_mds_solver("nystrom"), Error);
  o.solver = MdsSolver::Full;
  EXPECT_FALSE(mds_uses_landmarks(o, 1000000, 1e9));
  o.solver = MdsSolver::Landmarks;
  EXPECT_TRUE(mds_uses_landmarks(o, 10, 1e12));
  o.solver = MdsSolver::Auto;
  EXPECT_FALSE(mds_uses_landmarks(o, 5000, 1e12));
  EXPECT_FALSE(mds_uses_landmarks(o, 5000, -1));                           // unknown memory
  EXPECT_TRUE(mds_uses_landmarks(o, o.auto_full_max_vertices + 1, 1e15));  // size
  EXPECT_TRUE(mds_uses_landmarks(o, 5000, 1.9e8));                         // 100 MB of 190 MB
}

TEST(LandmarkMds, RefusesBadRows) {
  Eigen::MatrixXf rows = Eigen::MatrixXf::Ones(4, 10);
  EXPECT_THROW(landmark_classical_mds(rows, {0, 1, 2}), Error);             // count mismatch
  EXPECT_THROW(landmark_classical_mds(rows.topRows(3), {0, 1, 2}), Error);  // fewer than 4
  EXPECT_THROW(landmark_classical_mds(rows, {0, 1, 2, 2}), Error);          // twice
  EXPECT_THROW(landmark_classical_mds(rows, {0, 1, 2, 10}), Error);         // out of range
  rows(2, 5) = std::numeric_limits<float>::infinity();
  EXPECT_THROW(landmark_classical_mds(rows, {0, 1, 2, 3}), Error);
}

}  // namespace landmark_mds_test
}  // namespace cshapes
