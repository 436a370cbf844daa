#include "cshapes/mesh/subdivide.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <set>

#include "cshapes/support/error.h"
#include "cshapes/data/synthetic.h"
#include "tests/test_support.h"

namespace cshapes {
namespace subdivide_test {

using test::signed_volume;

double max_edge_length(const Mesh& m) {
  return edge_lengths(m.V, mesh_edges(m.F)).maxCoeff();
}

// Every vertex past the input's lies on the input surface (in one of its triangles: a midpoint of an input
// edge, or of a segment inside a triangle after several rounds), and the input's vertices come first.
void expect_new_vertices_on_input_surface(const Mesh& input, const Mesh& refined) {
  const Index n = input.num_vertices();
  ASSERT_GE(refined.num_vertices(), n);
  EXPECT_EQ(refined.V.topRows(n), input.V);
  const double scale = max_edge_length(input);
  for (Index i = n; i < refined.num_vertices(); ++i) {
    const Eigen::Vector3d p = refined.V.row(i).transpose();
    double closest = 1e300;
    for (Index f = 0; f < input.num_faces(); ++f) {
      const Eigen::Vector3d a = input.V.row(input.F(f, 0)), b = input.V.row(input.F(f, 1)),
                            c = input.V.row(input.F(f, 2));
      const Eigen::Vector3d normal = (b - a).cross(c - a);
      const double twice_area = normal.norm();
      // Barycentric coordinates of p's projection; inside (to rounding) → distance to the plane.
      const double u = (c - b).cross(p - b).dot(normal) / (twice_area * twice_area);
      const double v = (a - c).cross(p - c).dot(normal) / (twice_area * twice_area);
      if (u < -1e-12 || v < -1e-12 || u + v > 1 + 1e-12) continue;
      closest = std::min(closest, std::abs((p - a).dot(normal)) / twice_area);
    }
    EXPECT_LT(closest, 1e-12 * scale) << "vertex " << i;
  }
}

TEST(MidpointSubdivide, IcosahedronKnownCountsAndInvariants) {
  const Mesh ico = icosphere(0);
  const Mesh sub = midpoint_subdivide(ico);
  EXPECT_EQ(sub.num_vertices(), 12 + 30);
  EXPECT_EQ(sub.num_faces(), 80);
  const MeshInfo before = mesh_info(ico), after = mesh_info(sub);
  EXPECT_EQ(after.euler_characteristic, before.euler_characteristic);
  EXPECT_EQ(after.boundary_edges, 0);
  EXPECT_NEAR(after.area, before.area, 1e-12 * before.area);  // flat 1-to-4 split: the same surface
  EXPECT_NEAR(signed_volume(sub), signed_volume(ico),
              1e-12 * std::abs(signed_volume(ico)));  // orientation kept
  const Edges E = mesh_edges(ico.F);
  for (Index e = 0; e < E.rows(); ++e)  // vertex n + e is the midpoint of edge e
    EXPECT_LT((sub.V.row(12 + e) - 0.5 * (ico.V.row(E(e, 0)) + ico.V.row(E(e, 1)))).norm(), 1e-15);
  EXPECT_NEAR(max_edge_length(sub), 0.5 * max_edge_length(ico), 1e-12);
}

TEST(SplitLongestEdges, ExactCountSameSurfaceShorterEdges) {
  for (const Mesh& input : {icosphere(1), grid(5, 4, 2.0, 1.0), torus(8, 5)}) {
    const MeshInfo before = mesh_info(input);
    for (Index extra : {Index(1), Index(7), before.vertices + 3}) {
      const Index target = before.vertices + extra;
      const Mesh out = split_longest_edges(input, target);
      ASSERT_EQ(out.num_vertices(), target);
      const MeshInfo after = mesh_info(out);
      EXPECT_EQ(after.euler_characteristic, before.euler_characteristic);
      EXPECT_EQ(after.boundary_loops, before.boundary_loops);
      EXPECT_EQ(after.components, before.components);
      EXPECT_EQ(after.genus, before.genus);
      EXPECT_NEAR(after.area, before.area, 1e-12 * before.area);
      EXPECT_LE(max_edge_length(out), max_edge_length(input) * (1 + 1e-15));
      EXPECT_NEAR(signed_volume(out), signed_volume(input), 1e-12 * (1 + std::abs(signed_volume(input))));
      expect_new_vertices_on_input_surface(input, out);
    }
  }
  // The longest edge goes first: one split of a grid with a single long edge direction.
  const Mesh stretched = grid(2, 2, 10.0, 1.0);  // two triangles: the diagonal is the longest edge
  const Mesh one = split_longest_edges(stretched, 5);
  const Eigen::RowVector3d middle(5.0, 0.5, 0.0);
  EXPECT_LT((one.V.row(4) - middle).norm(), 1e-12);
}

TEST(SplitLongestEdges, NoOpAndRefusal) {
  const Mesh ico = icosphere(0);
  const Mesh same = split_longest_edges(ico, 12);
  EXPECT_EQ(same.V, ico.V);
  EXPECT_EQ(same.F, ico.F);
  Mesh cloud;
  cloud.V = ico.V;
  EXPECT_THROW(split_longest_edges(cloud, 13), Error);
}

TEST(RefineToVertexCount, SubdivisionsThenSplits) {
  // 12 → 42 → 162 vertices by subdivision (642 would overshoot 500), then 338 splits.
  const RefineToVertexCountResult r = refine_to_vertex_count(icosphere(0), 500);
  EXPECT_EQ(r.mesh.num_vertices(), 500);
  EXPECT_EQ(r.subdivisions, 2);
  EXPECT_EQ(r.edge_splits, 338);
  EXPECT_EQ(mesh_info(r.mesh).euler_characteristic, 2);
  EXPECT_EQ(refine_to_vertex_count(icosphere(0), 42).subdivisions, 1);
  EXPECT_EQ(refine_to_vertex_count(icosphere(0), 42).edge_splits, 0);
}

}  // namespace subdivide_test
}  // namespace cshapes
