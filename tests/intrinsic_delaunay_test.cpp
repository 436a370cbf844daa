#include "core/intrinsic_delaunay.h"

#include <gtest/gtest.h>

#include <random>

#include "core/io.h"
#include "core/synthetic.h"
#include "tests/test_support.h"

namespace cshapes {
namespace {

double total_area(const IntrinsicTriangulation& T) {
  double sum = 0;
  for (Index f = 0; f < T.F.rows(); ++f) sum += intrinsic_face_area(T, f);
  return sum;
}

// A flat grid stretched 5× along x with jittered vertices: many edges far from Delaunay.
Mesh stretched_grid() {
  Mesh m = grid(30, 30, 5.0, 1.0);
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> u(-0.01, 0.01);
  for (Index i = 0; i < m.num_vertices(); ++i) m.V(i, 1) += (m.V(i, 1) > 0 && m.V(i, 1) < 1) ? u(rng) : 0.0;
  return m;
}

TEST(IntrinsicDelaunay, FlatMeshGetsStraightEdges) {
  Mesh m = stretched_grid();
  IntrinsicTriangulation before = intrinsic_triangulation(m);
  ASSERT_GT(non_delaunay_edges(before), 100);
  IntrinsicTriangulation T = intrinsic_delaunay(m);
  EXPECT_GT(T.flips, 100);
  EXPECT_EQ(non_delaunay_edges(T), 0);
  EXPECT_EQ(T.F.rows(), m.F.rows());
  EXPECT_NEAR(total_area(T), 5.0, 1e-9);
  // In the plane (a convex domain) every flipped edge is the straight segment between its end points.
  for (Index f = 0; f < T.F.rows(); ++f)
    for (int k = 0; k < 3; ++k)
      EXPECT_NEAR(T.length(f, k), (m.V.row(T.F(f, k)) - m.V.row(T.F(f, (k + 1) % 3))).norm(), 1e-9);
}

TEST(IntrinsicDelaunay, DelaunayMeshIsUnchanged) {
  Mesh m = icosphere(3);  // near-equilateral triangles: already Delaunay
  IntrinsicTriangulation T = intrinsic_delaunay(m);
  EXPECT_EQ(T.flips, 0);
  EXPECT_EQ(T.F, m.F);
}

TEST(IntrinsicDelaunay, TOSCACatKeepsAreaAndTopology) {
  CSHAPES_REQUIRE_DATA();
  Mesh cat = read_mesh(test::tosca5k("cat0"));
  IntrinsicTriangulation before = intrinsic_triangulation(cat);
  IntrinsicTriangulation T = intrinsic_delaunay(cat);
  EXPECT_GT(non_delaunay_edges(before), 0);
  EXPECT_EQ(non_delaunay_edges(T), 0);
  EXPECT_NEAR(total_area(T), total_area(before), 1e-9 * total_area(before));
  // Every vertex keeps at least one face (flips never isolate a vertex).
  std::vector<int> degree(cat.num_vertices(), 0);
  for (Index f = 0; f < T.F.rows(); ++f)
    for (int k = 0; k < 3; ++k) ++degree[T.F(f, k)];
  for (int d : degree) EXPECT_GT(d, 0);
  // Intrinsic edges are geodesics across the surface: never shorter than the straight chord.
  for (Index f = 0; f < T.F.rows(); ++f)
    for (int k = 0; k < 3; ++k)
      EXPECT_GE(T.length(f, k), (cat.V.row(T.F(f, k)) - cat.V.row(T.F(f, (k + 1) % 3))).norm() * (1 - 1e-9));
}

}  // namespace
}  // namespace cshapes
