#include "cshapes/operators/intrinsic_delaunay.h"

#include <gtest/gtest.h>

#include <random>

#include "cshapes/mesh/io.h"
#include "cshapes/data/stress_corpus.h"
#include "cshapes/data/synthetic.h"
#include "tests/test_support.h"

namespace cshapes {
namespace intrinsic_delaunay_test {

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


// Faces that are no triangles at all: a corner on the opposite edge (zero area) and two coincident corners
// (a zero-length edge). Mollification lengthens every edge by the same small δ, so every face becomes a true
// triangle; nothing else changes by more than δ.
TEST(IntrinsicDelaunay, DegenerateFacesAreMollified) {
  Mesh m = icosphere(3);
  const int a = m.F(0, 0), b = m.F(0, 1), c = m.F(0, 2);
  m.V.row(c) = 0.5 * (m.V.row(a) + m.V.row(b));  // face 0 collinear
  const int d = m.F(100, 0), e = m.F(100, 1);
  m.V.row(e) = m.V.row(d);  // a zero-length edge
  const IntrinsicTriangulation raw = intrinsic_triangulation(m, 0.0);
  EXPECT_EQ(raw.mollification, 0.0);
  EXPECT_LE(triangle_inequality_margin(raw, 0), 1e-15);
  for (const IntrinsicTriangulation& T : {intrinsic_triangulation(m), intrinsic_delaunay(m)}) {
    EXPECT_EQ(intrinsic_triangulation_defect(m, T), "");
    EXPECT_GT(T.mollification, 0.0);
    EXPECT_LT(T.mollification, 2e-6 * T.margin / kMollifyFactor);  // about ε: 1e-6 of the mean edge
    for (Index f = 0; f < T.F.rows(); ++f) {
      EXPECT_GE(triangle_inequality_margin(T, f), 0.5 * T.margin * (1 - 1e-9)) << "face " << f;
      EXPECT_GT(intrinsic_face_area(T, f), 0.0) << "face " << f;
    }
  }
  // A mesh without nearly degenerate faces is not touched.
  EXPECT_EQ(intrinsic_triangulation(icosphere(3)).mollification, 0.0);
}

// Two faces sharing two edges (a vertex of degree 2, as flips produce): flipping one of the shared edges
// must keep the half-edge pairing mutual. A flat triangle (x, y, z) split at a point v very close to edge
// xy, closed by the same triangle seen from the back: the spokes v-x and v-y face angles near π, so the flips
// pass through vertices of degree 2 and self-folded triangles.
TEST(IntrinsicDelaunay, FlipsThroughLowDegreeVerticesKeepThePairing) {
  for (double t : {0.5, 0.1, 0.01}) {
    for (double gap : {1e-2, 1e-4, 1e-8}) {
      Mesh m;
      m.V.resize(4, 3);
      m.V << 0, 0, 0,  // x
          1, 0, 0,     // y
          0.3, 1, 0,   // z
          t, gap, 0;   // v, just above edge xy
      m.F.resize(4, 3);
      m.F << 3, 0, 1,  // v x y
          3, 1, 2,     // v y z
          3, 2, 0,     // v z x
          0, 2, 1;     // the back
      const IntrinsicTriangulation T = intrinsic_delaunay(m);
      EXPECT_EQ(intrinsic_triangulation_defect(m, T), "") << "t " << t << " gap " << gap;
      EXPECT_LE(non_delaunay_edges(T, 1e-6), T.skipped_flips);
    }
  }
}

// The failure-prone corpus (data/stress_corpus.h): on every kind of mesh the flips end in a valid intrinsic
// triangulation (pairing mutual and opposite, every face a true triangle, no vertex lost), with the area of
// the mollified input and no non-Delaunay edge left except those whose flip was refused.
TEST(IntrinsicDelaunay, StressCorpusSample) {
  StressCorpusOptions corpus;
  corpus.min_vertices = 200;
  corpus.max_vertices = 1500;
  for (Index i = 0; i < kStressKinds; ++i) {
    const StressCase c = stress_case(11, i, corpus);
    const Mesh m = make_stress_mesh(c, corpus);
    const IntrinsicTriangulation before = intrinsic_triangulation(m);
    const IntrinsicTriangulation T = intrinsic_delaunay(m);
    EXPECT_EQ(intrinsic_triangulation_defect(m, T), "") << c.describe();
    EXPECT_NEAR(total_area(T), total_area(before), 1e-8 * total_area(before)) << c.describe();
    EXPECT_LE(non_delaunay_edges(T, 1e-6), T.skipped_flips) << c.describe();
  }
}

}  // namespace intrinsic_delaunay_test
}  // namespace cshapes
