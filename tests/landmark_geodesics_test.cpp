#include "cshapes/geodesics/landmark_geodesics.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <numeric>
#include <random>
#include <set>
#include <vector>

#include "cshapes/support/error.h"
#include "cshapes/data/synthetic.h"

namespace cshapes {
namespace landmark_geodesics_test {

double mean_edge(const Mesh& m) {
  return edge_lengths(m.V, mesh_edges(m.F)).mean();
}

// Each landmark's row is the all-pairs matrix's row (the same solver, symmetrised there) within the method's
// asymmetry, a fraction of an edge; the graph method's rows are exact on its graph, so equal to rounding.
TEST(LandmarkGeodesics, RowsAreTheAllPairsRows) {
  const Mesh m = torus(48, 16, 2.0, 0.7);
  const double h = mean_edge(m);
  for (GeodesicMethod method : {GeodesicMethod::Heat, GeodesicMethod::FastMarching, GeodesicMethod::Graph}) {
    LandmarkGeodesicsOptions options;
    options.count = 12;
    options.geodesics.method = method;
    const LandmarkGeodesics lg = landmark_geodesics(m, options);
    const DistanceMatrix D = all_pairs_geodesics(m, options.geodesics);
    ASSERT_EQ(lg.rows.rows(), 12);
    ASSERT_EQ(lg.rows.cols(), m.num_vertices());
    for (Index k = 0; k < lg.rows.rows(); ++k) {
      const double gap = (lg.rows.row(k) - D.row(lg.landmarks[k])).cwiseAbs().maxCoeff();
      EXPECT_LT(gap, method == GeodesicMethod::Graph ? 1e-5 * D.maxCoeff() : 0.5 * h)
          << to_string(method) << " landmark " << k;
      EXPECT_EQ(lg.rows(k, lg.landmarks[k]), 0.0f);
    }
    // The same rows for given landmarks (computed in parallel) as in the sampling.
    const Eigen::MatrixXf again = geodesic_rows_from(m, lg.landmarks, options.geodesics);
    EXPECT_EQ((again - lg.rows).cwiseAbs().maxCoeff(), 0.0f) << to_string(method);
  }
}

// Farthest-point sampling by brute force from the rows: landmark k is the vertex farthest from landmarks
// 0..k-1 (the first the one farthest from the hint), all distinct; the coverage radius is the largest
// nearest-landmark distance and shrinks as L grows.
TEST(LandmarkGeodesics, FarthestPointSamplingByBruteForce) {
  const Mesh m = icosphere(3);
  LandmarkGeodesicsOptions options;
  options.count = 20;
  options.geodesics.method = GeodesicMethod::Graph;
  const LandmarkGeodesics lg = landmark_geodesics(m, options);
  // The first landmark: the vertex farthest from the central one (nearest the centroid).
  const Eigen::VectorXd from_hint =
      geodesic_distances(m, {static_cast<int>(central_vertex(m.V))}, options.geodesics);
  EXPECT_DOUBLE_EQ(from_hint[lg.landmarks[0]], from_hint.maxCoeff());
  EXPECT_EQ(std::set<int>(lg.landmarks.begin(), lg.landmarks.end()).size(), lg.landmarks.size());
  for (size_t k = 1; k < lg.landmarks.size(); ++k) {
    const Eigen::VectorXf nearest = lg.rows.topRows(k).colwise().minCoeff().transpose();
    EXPECT_FLOAT_EQ(nearest[lg.landmarks[k]], nearest.maxCoeff()) << "landmark " << k;
  }
  const Eigen::VectorXf nearest = lg.rows.colwise().minCoeff().transpose();
  EXPECT_NEAR(lg.coverage_radius, nearest.maxCoeff(), 1e-5);
  options.count = 80;
  const LandmarkGeodesics more = landmark_geodesics(m, options);
  EXPECT_LT(more.coverage_radius, lg.coverage_radius);
  // The first 20 of 80 are the same 20: sampling is greedy.
  EXPECT_TRUE(std::equal(lg.landmarks.begin(), lg.landmarks.end(), more.landmarks.begin()));
}

TEST(LandmarkGeodesics, AsManyLandmarksAsVerticesTakesEveryVertex) {
  const Mesh m = icosphere(1);
  LandmarkGeodesicsOptions options;
  options.count = 10 * m.num_vertices();  // clamped to n
  const LandmarkGeodesics lg = landmark_geodesics(m, options);
  ASSERT_EQ(static_cast<Index>(lg.landmarks.size()), m.num_vertices());
  EXPECT_EQ(std::set<int>(lg.landmarks.begin(), lg.landmarks.end()).size(), lg.landmarks.size());
  EXPECT_EQ(lg.coverage_radius, 0.0);
}

TEST(LandmarkGeodesics, RefusesBadInput) {
  Mesh a = icosphere(1);
  Mesh two;
  two.V.resize(2 * a.num_vertices(), 3);
  two.V << a.V, (a.V.rowwise() + Eigen::RowVector3d(5, 0, 0));
  two.F.resize(2 * a.num_faces(), 3);
  two.F << a.F, (a.F.array() + static_cast<int>(a.num_vertices())).matrix();
  EXPECT_THROW(landmark_geodesics(two), Error);
  LandmarkGeodesicsOptions options;
  options.count = 0;
  EXPECT_THROW(landmark_geodesics(a, options), Error);
  options.count = 3;
  options.first_hint = static_cast<int>(a.num_vertices());
  EXPECT_THROW(landmark_geodesics(a, options), Error);
  EXPECT_THROW(geodesic_rows_from(a, {0, -1}), Error);
}

}  // namespace landmark_geodesics_test
}  // namespace cshapes

namespace cshapes {
namespace landmark_geodesics_test {

// A point set's graph (here a mesh's edges, given as a graph): the same landmarks and rows as the mesh's
// graph geodesics.
TEST(LandmarkGeodesics, GraphSolverOnGivenEdges) {
  const Mesh m = icosphere(2);
  LandmarkGeodesicsOptions options;
  options.count = 9;
  options.geodesics.method = GeodesicMethod::Graph;
  const LandmarkGeodesics on_mesh = landmark_geodesics(m, options);
  const SingleSourceGeodesics graph(m.V, mesh_edges(m.F));
  const LandmarkGeodesics on_graph = landmark_geodesics(graph, m.V, 9);
  EXPECT_EQ(on_graph.landmarks, on_mesh.landmarks);
  EXPECT_EQ((on_graph.rows - on_mesh.rows).cwiseAbs().maxCoeff(), 0.0f);
  Edges two_pieces(1, 2);
  two_pieces << 0, 1;
  EXPECT_THROW(SingleSourceGeodesics(m.V.topRows(3), two_pieces), Error);
}

// Farthest-point sampling is a function of the geometry: on a renumbered mesh it picks the same points
// (the first from the central vertex, ties by position), and the rows follow them.
TEST(LandmarkGeodesics, ARenumberedMeshGetsTheSameLandmarks) {
  const Mesh m = icosphere(3);  // symmetric: distances tie everywhere
  std::vector<int> order(static_cast<size_t>(m.num_vertices()));
  std::iota(order.begin(), order.end(), 0);
  std::mt19937 random(3);
  std::shuffle(order.begin(), order.end(), random);
  Mesh r;
  r.V.resize(m.V.rows(), 3);
  std::vector<int> new_index(order.size());
  for (size_t k = 0; k < order.size(); ++k) {
    r.V.row(static_cast<Index>(k)) = m.V.row(order[k]);
    new_index[static_cast<size_t>(order[k])] = static_cast<int>(k);
  }
  r.F = m.F;
  for (Index f = 0; f < r.F.rows(); ++f)
    for (int c = 0; c < 3; ++c) r.F(f, c) = new_index[static_cast<size_t>(m.F(f, c))];
  LandmarkGeodesicsOptions options;
  options.count = 12;
  options.geodesics.method = GeodesicMethod::Graph;
  const LandmarkGeodesics a = landmark_geodesics(m, options), b = landmark_geodesics(r, options);
  ASSERT_EQ(a.landmarks.size(), b.landmarks.size());
  for (size_t k = 0; k < a.landmarks.size(); ++k) {
    EXPECT_EQ(order[static_cast<size_t>(b.landmarks[k])], a.landmarks[k]) << k;
    for (Index j = 0; j < m.num_vertices(); ++j)
      ASSERT_NEAR(b.rows(static_cast<Index>(k), new_index[static_cast<size_t>(j)]), a.rows(static_cast<Index>(k), j),
                  1e-5f)
          << k << " " << j;
  }
}

}  // namespace landmark_geodesics_test
}  // namespace cshapes
