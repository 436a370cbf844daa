#include "cshapes/canon/form_quality.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "cshapes/mesh/mesh.h"
#include "cshapes/data/synthetic.h"

namespace cshapes {
namespace form_quality_test {

TEST(FormQuality, IdentityFormHasStretchOne) {
  const Mesh m = icosphere(2);
  const Edges E = mesh_edges(m.F);
  const FormQuality q = form_quality(m.V, E, m.V);
  EXPECT_TRUE(q.ok) << q.description;
  EXPECT_NEAR(q.max_stretch, 1.0, 1e-12);
  EXPECT_NEAR(q.p99_stretch, 1.0, 1e-12);
  EXPECT_NEAR(q.mean_stretch, 1.0, 1e-12);
  EXPECT_NEAR(q.min_stretch, 1.0, 1e-12);
  EXPECT_EQ(q.edges_measured, E.rows());
  EXPECT_EQ(q.runaway_vertices, 0);
  EXPECT_TRUE(q.runaway_examples.empty());
  EXPECT_EQ(q.description.rfind("ok:", 0), 0u) << q.description;
}

TEST(FormQuality, RigidlyMovedAndScaledFormHasStretchEqualToTheScale) {
  const Mesh m = torus(24, 12, 2.0, 0.5);
  const Edges E = mesh_edges(m.F);
  const Eigen::Matrix3d R = Eigen::AngleAxisd(0.7, Eigen::Vector3d(1, 2, 3).normalized()).toRotationMatrix();
  for (double scale : {0.5, 1.7}) {
    const Points X = ((scale * m.V * R.transpose()).rowwise() + Eigen::RowVector3d(10, -3, 4)).eval();
    const FormQuality q = form_quality(m.V, E, X);
    EXPECT_NEAR(q.max_stretch, scale, 1e-12 * scale);
    EXPECT_NEAR(q.p99_stretch, scale, 1e-12 * scale);
    EXPECT_NEAR(q.mean_stretch, scale, 1e-12 * scale);
    EXPECT_TRUE(q.ok) << q.description;  // moved as a whole: nothing ran away
  }
}

TEST(FormQuality, PercentileIgnoresOneStretchedEdgeAndMaxSeesIt) {
  // A grid with one vertex pulled a little: its edges are the only ones stretched.
  const Mesh m = grid(20, 20);
  const Edges E = mesh_edges(m.F);
  Points X = m.V;
  const Index moved = 10 * 20 + 10;
  const double spacing = 1.0 / 19;
  X(moved, 2) += 2 * spacing;  // out of the plane: its edges grow √5× (axis) and √3× (diagonal)
  const FormQuality q = form_quality(m.V, E, X);
  const Eigen::VectorXd before = edge_lengths(m.V, E), after = edge_lengths(X, E);
  EXPECT_NEAR(q.max_stretch, (after.array() / before.array()).maxCoeff(), 1e-12);
  EXPECT_GT(q.max_stretch, 2.0);
  EXPECT_NEAR(q.p99_stretch, 1.0, 1e-12);  // 6 stretched edges of 1,121: above the 99th percentile
  EXPECT_TRUE(q.ok) << q.description;      // stretched 2.2× an edge: under the 5× limit
}

TEST(FormQuality, VertexMovedFarAwayIsFlagged) {
  const Mesh m = icosphere(2);  // diameter 2, bbox diagonal 2√3
  const Edges E = mesh_edges(m.F);
  Points X = m.V;
  X.row(17) += Eigen::RowVector3d(30, 0, 0);  // ≈ 9 bbox diagonals away
  const FormQuality q = form_quality(m.V, E, X);
  EXPECT_FALSE(q.ok);
  EXPECT_EQ(q.far_vertices, 1);
  // Its neighbours are flagged too: each ends an edge stretched far over 5× the mean edge length.
  const Adjacency adj = adjacency(m.num_vertices(), E);
  const int neighbours = adj.offsets[18] - adj.offsets[17];
  EXPECT_EQ(q.overstretched_edges, neighbours);
  EXPECT_EQ(q.stretched_vertices, neighbours + 1);
  EXPECT_EQ(q.runaway_vertices, neighbours + 1);
  ASSERT_FALSE(q.runaway_examples.empty());
  EXPECT_NE(std::find(q.runaway_examples.begin(), q.runaway_examples.end(), 17), q.runaway_examples.end());
  const double expected = (X.row(17) - X.colwise().mean()).norm() / bbox_diagonal(m.V);
  EXPECT_NEAR(q.max_distance, expected, 0.5 / bbox_diagonal(m.V));  // the median is within the unit sphere
  EXPECT_EQ(q.description.rfind("NOT OK", 0), 0u) << q.description;
}

TEST(FormQuality, TornEdgesAreLeftOutAndACutOffPartIsDetached) {
  // A strip of 10 × 3 vertices; tear the edges between columns 7 and 8: columns 8-9 are cut off.
  const Mesh m = grid(10, 3);
  const Edges E = mesh_edges(m.F);
  std::vector<bool> torn(E.rows(), false);
  auto column = [](int v) { return v % 10; };
  Points X = m.V;
  for (Index e = 0; e < E.rows(); ++e) {
    const int a = std::min(column(E(e, 0)), column(E(e, 1))), b = std::max(column(E(e, 0)), column(E(e, 1)));
    if (a == 7 && b == 8) torn[e] = true;
  }
  for (Index i = 0; i < X.rows(); ++i)
    if (column(static_cast<int>(i)) >= 8)
      X(i, 0) += 0.5;  // the cut-off part moved, rigidly: no kept edge stretched
  const FormQuality with_tears = form_quality(m.V, E, X, &torn);
  EXPECT_NEAR(with_tears.max_stretch, 1.0, 1e-12);
  EXPECT_EQ(with_tears.overstretched_edges, 0);
  EXPECT_EQ(with_tears.detached_vertices, 6);  // columns 8 and 9, three rows
  EXPECT_EQ(with_tears.runaway_vertices, 6);
  EXPECT_FALSE(with_tears.ok);
  // Without the torn flags the same edges count: stretched, but not detached.
  const FormQuality without = form_quality(m.V, E, X);
  EXPECT_GT(without.max_stretch, 2.0);
  EXPECT_EQ(without.detached_vertices, 0);
}

TEST(FormQuality, NonFiniteFormIsNotOk) {
  const Mesh m = icosphere(1);
  const Edges E = mesh_edges(m.F);
  Points X = m.V;
  X(3, 1) = std::nan("");
  const FormQuality q = form_quality(m.V, E, X);
  EXPECT_FALSE(q.ok);
  EXPECT_GE(q.far_vertices, 1);
  EXPECT_TRUE(std::isnan(q.max_stretch));
}

TEST(FormQuality, TornFlagsMatchEitherOrientation) {
  Edges E(3, 2), torn(2, 2);
  E << 0, 1, 1, 2, 0, 2;
  torn << 2, 1, 5, 6;
  const std::vector<bool> flags = torn_edge_flags(E, torn);
  EXPECT_EQ(flags, (std::vector<bool>{false, true, false}));
}

TEST(FormQuality, RejectsMismatchedSizes) {
  const Mesh m = icosphere(1);
  const Edges E = mesh_edges(m.F);
  EXPECT_ANY_THROW(form_quality(m.V, E, m.V.topRows(5)));
  std::vector<bool> torn(3, false);
  EXPECT_ANY_THROW(form_quality(m.V, E, m.V, &torn));
}

}  // namespace form_quality_test
}  // namespace cshapes

namespace cshapes {
namespace form_quality_test {

// A collapsed form can never pass: `canon --method smacof` on a mesh scaled by 1e20 gave 600 rows "0 0 0"
// with "ok: stretch max 0". All-zero rows, a form shrunk to a point at any scale, and two neighbours
// merged are each flagged; the intact form at the same scales passes.
TEST(FormQuality, ACollapsedFormFailsAtAnyScale) {
  const Mesh m = icosphere(2);
  const Edges E = mesh_edges(m.F);
  const FormQuality zero = form_quality(m.V, E, Points::Zero(m.V.rows(), 3));
  EXPECT_FALSE(zero.ok) << zero.description;
  EXPECT_EQ(zero.coincident_vertices, m.V.rows());
  EXPECT_EQ(zero.description.rfind("NOT OK:", 0), 0u) << zero.description;
  EXPECT_NE(zero.description.find("coincident"), std::string::npos) << zero.description;
  for (double s : {1e-20, 1.0, 1e20}) {
    SCOPED_TRACE(s);
    const Points V = s * m.V;
    EXPECT_TRUE(form_quality(V, E, V).ok);
    const Points point = (Points::Ones(m.V.rows(), 3) * (3 * s)).eval();
    EXPECT_FALSE(form_quality(V, E, point).ok);
    Points merged = V;
    merged.row(E(0, 1)) = merged.row(E(0, 0));
    const FormQuality q = form_quality(V, E, merged);
    EXPECT_FALSE(q.ok) << q.description;
    EXPECT_EQ(q.coincident_vertices, 2);
    EXPECT_EQ(q.runaway_examples.front(), std::min(E(0, 0), E(0, 1)));
  }
}

TEST(FormQuality, AReasonFromTheMethodMakesItNotOk) {
  const Mesh m = icosphere(1);
  FormQuality q = form_quality(m.V, mesh_edges(m.F), m.V);
  ASSERT_TRUE(q.ok);
  fail_form_quality(q, "normalised stress nan");
  EXPECT_FALSE(q.ok);
  EXPECT_EQ(q.description.rfind("NOT OK: normalised stress nan; edge stretch (form length / input length) max 1", 0), 0u) << q.description;
}

}  // namespace form_quality_test
}  // namespace cshapes
