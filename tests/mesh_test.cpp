#include "cshapes/mesh/mesh.h"

#include <gtest/gtest.h>

#include <cmath>

#include "cshapes/support/error.h"
#include "cshapes/mesh/io.h"
#include "cshapes/data/synthetic.h"
#include "tests/test_support.h"

namespace cshapes {
namespace mesh_test {

constexpr double kPi = 3.14159265358979323846;

TEST(Synthetic, IcosphereCountsAndArea) {
  for (int s = 0; s <= 4; ++s) {
    Mesh m = icosphere(s);
    MeshInfo info = mesh_info(m);
    long f = 20L << (2 * s);
    EXPECT_EQ(info.vertices, f / 2 + 2);
    EXPECT_EQ(info.faces, f);
    EXPECT_EQ(info.edges, 3 * f / 2);
    EXPECT_EQ(info.euler_characteristic, 2);
    EXPECT_EQ(info.genus, 0);
    EXPECT_EQ(info.components, 1);
    EXPECT_EQ(info.boundary_edges, 0);
  }
  // The inscribed polyhedron converges to the sphere's area from below.
  double area = mesh_info(icosphere(5)).area;
  EXPECT_LT(area, 4 * kPi);
  EXPECT_NEAR(area, 4 * kPi, 4 * kPi * 2e-3);
}

TEST(Synthetic, TorusIsGenusOne) {
  Mesh m = torus(64, 32, 2.0, 0.5);
  MeshInfo info = mesh_info(m);
  EXPECT_EQ(info.vertices, 64 * 32);
  EXPECT_EQ(info.faces, 2 * 64 * 32);
  EXPECT_EQ(info.euler_characteristic, 0);
  EXPECT_EQ(info.genus, 1);
  EXPECT_NEAR(info.area, 4 * kPi * kPi * 2.0 * 0.5, 4 * kPi * kPi * 2.0 * 0.5 * 5e-3);
}

TEST(Synthetic, GridIsAFlatDisk) {
  Mesh m = grid(11, 7, 2.0, 3.0);
  MeshInfo info = mesh_info(m);
  EXPECT_EQ(info.vertices, 77);
  EXPECT_EQ(info.faces, 2 * 10 * 6);
  EXPECT_EQ(info.euler_characteristic, 1);
  EXPECT_EQ(info.boundary_edges, 2 * (10 + 6));
  EXPECT_EQ(info.boundary_loops, 1);
  EXPECT_EQ(info.genus, 0);
  EXPECT_NEAR(info.area, 6.0, 1e-12);
  EXPECT_NEAR(info.bbox_diagonal, std::sqrt(13.0), 1e-12);
}

TEST(Synthetic, SwissRollHasThePapersSizeAndItsLength) {
  SwissRollOptions o;
  Mesh m = swiss_roll(o);
  MeshInfo info = mesh_info(m);
  EXPECT_EQ(info.vertices, 561);
  EXPECT_EQ(info.euler_characteristic, 1);
  // Polyline length along one row approaches the analytic arc length from below.
  double polyline = 0;
  for (int i = 0; i + 1 < o.nu; ++i) polyline += (m.V.row(i + 1) - m.V.row(i)).norm();
  double exact = swiss_roll_length(o.t0, o.t1);
  EXPECT_LT(polyline, exact);
  EXPECT_NEAR(polyline, exact, exact * 0.01);
  EXPECT_NEAR(info.area, exact * o.height, exact * o.height * 0.01);
}

// The resolution as an iteration stepping by the mean edge sees it, on grids of m × m vertices whose cells
// (dx × dy, one diagonal each) give a known mean edge: A / (√3/2 · h̄²) from the edge counts; an anisotropic
// grid (dy = 3 dx) has the same vertex count at a lower resolution; the measure ignores the coordinates' scale;
// the icosphere's nearly equilateral triangles give about its vertex count.
TEST(Mesh, EvenTriangulationVerticesKnownAnswers) {
  auto grid = [](int m, double dx, double dy, double scale) {
    Mesh g;
    g.V.resize(m * m, 3);
    for (int j = 0; j < m; ++j)
      for (int i = 0; i < m; ++i) g.V.row(j * m + i) << scale * i * dx, scale * j * dy, 0.0;
    g.F.resize(2 * (m - 1) * (m - 1), 3);
    Index f = 0;
    for (int j = 0; j + 1 < m; ++j)
      for (int i = 0; i + 1 < m; ++i) {
        const int a = j * m + i, b = a + 1, c = a + m, d = c + 1;
        g.F.row(f++) << a, b, d;
        g.F.row(f++) << a, d, c;
      }
    return g;
  };
  for (const double aspect : {1.0, 3.0}) {
    const int m = 21;
    const double dx = 0.1, dy = aspect * dx, cells = (m - 1.0) * (m - 1.0), sides = m * (m - 1.0);
    const double mean_edge = (sides * dx + sides * dy + cells * std::hypot(dx, dy)) / (2 * sides + cells);
    const double expected = cells * dx * dy / (std::sqrt(3.0) / 2 * mean_edge * mean_edge);
    for (const double scale : {1.0, 1e12, 1e-12}) {
      SCOPED_TRACE(testing::Message() << "aspect " << aspect << ", scale " << scale);
      const Mesh g = grid(m, dx, dy, scale);
      EXPECT_NEAR(even_triangulation_vertices(g.V, g.F), expected, 1e-9 * expected);
    }
  }
  const Mesh square = grid(21, 0.1, 0.1, 1.0), stretched = grid(21, 0.1, 0.3, 1.0);
  EXPECT_LT(even_triangulation_vertices(stretched.V, stretched.F),
            0.75 * even_triangulation_vertices(square.V, square.F));
  const Mesh sphere = icosphere(4);
  EXPECT_NEAR(even_triangulation_vertices(sphere.V, sphere.F) / sphere.num_vertices(), 1.0, 0.05);
  EXPECT_EQ(even_triangulation_vertices(sphere.V, Faces(0, 3)), 0.0);
}

TEST(Mesh, FromVectorsKeepsOrder) {
  const std::vector<Eigen::Vector3d> vertices = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
  const std::vector<Eigen::Vector3i> triangles = {{0, 2, 1}, {0, 1, 3}, {1, 2, 3}, {0, 3, 2}};
  const Mesh m = mesh_from_vectors(vertices, triangles);
  ASSERT_EQ(m.num_vertices(), 4);
  ASSERT_EQ(m.num_faces(), 4);
  for (Index i = 0; i < 4; ++i) EXPECT_EQ(m.V.row(i), vertices[i].transpose());
  for (Index f = 0; f < 4; ++f) EXPECT_EQ(m.F.row(f), triangles[f].transpose());
  EXPECT_EQ(mesh_info(m).euler_characteristic, 2);
  const Mesh empty = mesh_from_vectors({}, {});
  EXPECT_EQ(empty.num_vertices(), 0);
  EXPECT_TRUE(empty.is_point_cloud());
}

TEST(Mesh, AdjacencyIsSymmetricAndSorted) {
  Mesh m = icosphere(2);
  Edges E = mesh_edges(m.F);
  Adjacency adj = adjacency(m.num_vertices(), E);
  for (Index i = 0; i < m.num_vertices(); ++i) {
    for (int k = adj.offsets[i]; k < adj.offsets[i + 1]; ++k) {
      int j = adj.neighbors[k];
      if (k > adj.offsets[i]) {
        EXPECT_LT(adj.neighbors[k - 1], j);
      }
      const Eigen::RowVector2i& e = E.row(adj.edge_ids[k]);
      EXPECT_TRUE((e(0) == i && e(1) == j) || (e(0) == j && e(1) == i));
      // j lists i back
      bool back = false;
      for (int q = adj.offsets[j]; q < adj.offsets[j + 1]; ++q) back |= adj.neighbors[q] == i;
      EXPECT_TRUE(back);
    }
  }
}

TEST(Mesh, ComponentsAndLargestComponent) {
  Mesh a = icosphere(1), b = torus(8, 6);
  Mesh both;
  both.V.resize(a.V.rows() + b.V.rows(), 3);
  both.V << a.V, (b.V.rowwise() + Eigen::RowVector3d(5, 0, 0));
  both.F.resize(a.F.rows() + b.F.rows(), 3);
  both.F << a.F, (b.F.array() + static_cast<int>(a.V.rows())).matrix();
  MeshInfo info = mesh_info(both);
  EXPECT_EQ(info.components, 2);
  EXPECT_EQ(info.euler_characteristic, 2);
  EXPECT_EQ(info.genus, 1);
  EXPECT_THROW(require_connected(both, "two.off", false, nullptr), Error);
  std::string note;
  Submesh sub = require_connected(both, "two.off", true, &note);
  EXPECT_EQ(sub.mesh.num_vertices(), b.V.rows());  // the torus: 48 vertices against the sphere's 42
  EXPECT_EQ(mesh_info(sub.mesh).genus, 1);
  EXPECT_NE(note.find("two.off"), std::string::npos);
}

TEST(Mesh, ToscaCatIsAClosedSphere) {
  CSHAPES_REQUIRE_DATA();
  Mesh cat = read_mesh(test::tosca5k("cat0"));
  MeshInfo info = mesh_info(cat);
  EXPECT_EQ(info.vertices, 5000);
  EXPECT_EQ(info.faces, 9996);
  EXPECT_EQ(info.euler_characteristic, 2);
  EXPECT_EQ(info.components, 1);
  EXPECT_EQ(info.boundary_edges, 0);
  EXPECT_NEAR(info.bbox_diagonal, 224, 5);
}

}  // namespace mesh_test
}  // namespace cshapes

namespace cshapes {
namespace mesh_test {

TEST(Mesh, FiniteBboxDiagonalSkipsNonFiniteRows) {
  Points V(4, 3);
  V << 0, 0, 0, 3, 4, 0, NAN, 1, 1, 100, INFINITY, 0;
  EXPECT_DOUBLE_EQ(finite_bbox_diagonal(V), 5.0);  // the two finite rows: a 3-4-5 box
  EXPECT_DOUBLE_EQ(finite_bbox_diagonal(V.topRows(2)), bbox_diagonal(V.topRows(2)));
  EXPECT_EQ(finite_bbox_diagonal(V.bottomRows(2)), 0.0);
  EXPECT_EQ(finite_bbox_diagonal(Points(0, 3)), 0.0);
}

}  // namespace mesh_test
}  // namespace cshapes
