// mesh_defects: each defect kind on a mesh that has exactly that defect, with its known elements.
#include "cshapes/mesh/mesh_defects.h"

#include <gtest/gtest.h>

#include "cshapes/data/synthetic.h"
#include "tests/imperfect_meshes.h"

namespace cshapes {
namespace mesh_defects_test {

TEST(MeshDefects, CleanClosedMeshHasNone) {
  MeshDefects d = mesh_defects(icosphere(2));
  EXPECT_FALSE(d.any());
  EXPECT_EQ(d.summary(), "none");
  EXPECT_EQ(d.components, 1);
  EXPECT_EQ(d.boundary_edges, 0);
  // A grid: one boundary loop, not a defect.
  MeshDefects g = mesh_defects(grid(5, 4));
  EXPECT_FALSE(g.any());
  EXPECT_EQ(g.boundary_loops, 1);
  EXPECT_EQ(g.boundary_edges, 2 * (4 + 3));
}

// Issue 36: a mesh scaled by 1e155 had every face "zero-area" (squares overflow) and so did one scaled by
// 1e-155 (they underflow): the repair left 0 vertices. The test is a ratio, the same at any finite scale.
TEST(MeshDefects, ZeroAreaIsTheSameAtAnyScale) {
  Points V(4, 3);
  V << 0, 0, 0, 1, 0, 0, 0, 1, 0, 2, 1e-14, 0;  // face 0 a right triangle, face 1 a needle of zero area
  Faces F(2, 3);
  F << 0, 1, 2, 0, 1, 3;
  for (double s : {1e-300, 1e-155, 1.0, 1e155, 1e300}) {
    SCOPED_TRACE(s);
    const Points scaled = V * s;
    EXPECT_FALSE(face_has_zero_area(scaled, F, 0));
    EXPECT_TRUE(face_has_zero_area(scaled, F, 1));
  }
  EXPECT_EQ(mesh_defects(Mesh{icosphere(2).V * 1e155, icosphere(2).F}).zero_area_faces, 0);
  EXPECT_EQ(mesh_defects(Mesh{icosphere(2).V * 1e-155, icosphere(2).F}).zero_area_faces, 0);
}

TEST(MeshDefects, NonManifoldEdgeIsNamedWithItsFaces) {
  Mesh m = test::two_spheres_sharing(2);
  const test::EdgeAt e = test::rightmost_edge(icosphere(2));
  MeshDefects d = mesh_defects(m);
  ASSERT_EQ(d.nonmanifold_edges, 1);
  EXPECT_EQ(d.nonmanifold_edge_examples[0][0], std::min(e.a, e.b));
  EXPECT_EQ(d.nonmanifold_edge_examples[0][1], std::max(e.a, e.b));
  EXPECT_EQ(d.nonmanifold_edge_examples[0][2], 4);
  EXPECT_EQ(d.nonmanifold_vertices, 0);  // its endpoints are on the edge: not counted again
  EXPECT_EQ(d.duplicate_faces, 0);
  EXPECT_EQ(d.components, 1);
  EXPECT_NE(d.summary().find("1 non-manifold edge"), std::string::npos) << d.summary();
}

TEST(MeshDefects, PinchVertexIsNonManifold) {
  Mesh m = test::two_spheres_sharing(1);
  MeshDefects d = mesh_defects(m);
  EXPECT_EQ(d.nonmanifold_edges, 0);
  ASSERT_EQ(d.nonmanifold_vertices, 1);
  EXPECT_EQ(d.nonmanifold_vertex_examples[0], test::rightmost_edge(icosphere(2)).a);
  EXPECT_EQ(d.components, 1);
}

TEST(MeshDefects, IsolatedVertexAndComponents) {
  Mesh m = test::sphere_with_isolated_vertex();
  MeshDefects d = mesh_defects(m);
  EXPECT_EQ(d.isolated_vertices, 1);
  EXPECT_EQ(d.isolated_vertex_examples[0], m.num_vertices() - 1);
  EXPECT_EQ(d.components, 2);
  EXPECT_EQ(d.component_sizes, (std::vector<int>{162, 1}));

  MeshDefects two = mesh_defects(test::two_components());
  EXPECT_EQ(two.isolated_vertices, 0);
  EXPECT_EQ(two.components, 2);
  EXPECT_EQ(two.component_sizes, (std::vector<int>{162, 42}));
  EXPECT_NE(two.summary().find("2 components (162, 42 vertices)"), std::string::npos) << two.summary();
}

TEST(MeshDefects, DuplicateFaceIsADuplicateNotANonManifoldEdge) {
  Mesh m = test::sphere_with_duplicate_face();
  MeshDefects d = mesh_defects(m);
  ASSERT_EQ(d.duplicate_faces, 1);
  EXPECT_EQ(d.duplicate_face_examples[0][0], m.num_faces() - 1);
  EXPECT_EQ(d.duplicate_face_examples[0][1], 0);
  EXPECT_EQ(d.nonmanifold_edges, 0);
  EXPECT_EQ(d.nonmanifold_vertices, 0);
}

TEST(MeshDefects, RepeatedVertexZeroAreaAndZeroLength) {
  // A face naming a vertex twice.
  Mesh m = icosphere(1);
  m.F.conservativeResize(m.num_faces() + 1, 3);
  m.F.row(m.num_faces() - 1) << 0, 0, 1;
  MeshDefects d = mesh_defects(m);
  EXPECT_EQ(d.repeated_vertex_faces, 1);
  EXPECT_EQ(d.repeated_vertex_face_examples[0], m.num_faces() - 1);
  EXPECT_EQ(d.nonmanifold_edges, 0);  // the repeated-vertex face does not count on edge (0, 1)

  // Three collinear boundary vertices of a grid (0, 1, 2 on its first row) made a face: zero area, nothing
  // else.
  Mesh g = grid(4, 3);
  g.F.conservativeResize(g.num_faces() + 1, 3);
  g.F.row(g.num_faces() - 1) << 0, 1, 2;
  MeshDefects z = mesh_defects(g);
  EXPECT_EQ(z.zero_area_faces, 1);
  EXPECT_EQ(z.zero_area_face_examples[0], g.num_faces() - 1);
  EXPECT_EQ(z.nonmanifold_edges, 0);
  EXPECT_EQ(z.zero_length_edges, 0);

  // Two vertices of an edge moved onto each other: a zero-length edge; its faces have zero area.
  Mesh c = grid(4, 3);
  c.V.row(1) = c.V.row(0);
  MeshDefects l = mesh_defects(c);
  ASSERT_EQ(l.zero_length_edges, 1);
  EXPECT_EQ(l.zero_length_edge_examples[0], (std::array<int, 2>{0, 1}));
  EXPECT_GE(l.zero_area_faces, 1);
}

TEST(MeshDefects, ExamplesAreCappedAndCountsExact) {
  Mesh m = icosphere(1);
  const Index faces = m.num_faces();
  m.F.conservativeResize(2 * faces, 3);
  m.F.bottomRows(faces) = m.F.topRows(faces);
  MeshDefects d = mesh_defects(m);
  EXPECT_EQ(d.duplicate_faces, faces);
  EXPECT_EQ(d.duplicate_face_examples.size(), MeshDefects::max_examples);
  EXPECT_NE(d.summary().find("; ...)"), std::string::npos) << d.summary();
}

TEST(MeshDefects, PointCloudHasNone) {
  Mesh cloud;
  cloud.V = icosphere(1).V;
  MeshDefects d = mesh_defects(cloud);
  EXPECT_FALSE(d.any());
  EXPECT_EQ(d.isolated_vertices, 0);
}

}  // namespace mesh_defects_test
}  // namespace cshapes
