// repair_for: each requirement on a mesh with one defect; the result's invariants (no defect left that the
// requirements forbid, vertex_map back to input vertices at the same positions), strict refusal.
#include "cshapes/mesh/mesh_repair.h"

#include <gtest/gtest.h>

#include <cmath>

#include "cshapes/support/error.h"
#include "cshapes/mesh/mesh_defects.h"
#include "cshapes/data/synthetic.h"
#include "tests/imperfect_meshes.h"

namespace cshapes {
namespace mesh_repair_test {

// Every repaired vertex sits where its input vertex is, and every face of the result is an input face
// (through vertex_map).
void expect_consistent(const Mesh& input, const RepairedMesh& r) {
  ASSERT_EQ(static_cast<Index>(r.vertex_map.size()), r.mesh.num_vertices());
  EXPECT_EQ(r.input_vertices, input.num_vertices());
  for (Index k = 0; k < r.mesh.num_vertices(); ++k)
    EXPECT_EQ(r.mesh.V.row(k), input.V.row(r.vertex_map[k])) << "vertex " << k;
  std::set<std::array<int, 3>> input_faces;
  for (Index f = 0; f < input.num_faces(); ++f) input_faces.insert(sorted_face(input.F, f));
  for (Index f = 0; f < r.mesh.num_faces(); ++f) {
    std::array<int, 3> mapped = {r.vertex_map[r.mesh.F(f, 0)], r.vertex_map[r.mesh.F(f, 1)],
                                 r.vertex_map[r.mesh.F(f, 2)]};
    std::sort(mapped.begin(), mapped.end());
    EXPECT_TRUE(input_faces.count(mapped)) << "face " << f;
  }
}

TEST(MeshRepair, CleanMeshIsUnchanged) {
  Mesh m = icosphere(2);
  for (MeshRequirements req : {MeshRequirements::edge_graph(), MeshRequirements::manifold_surface()}) {
    RepairedMesh r = repair_for(m, req);
    EXPECT_FALSE(r.changed());
    EXPECT_EQ(r.text, "");
    EXPECT_EQ(r.mesh.V, m.V);
    EXPECT_EQ(r.mesh.F, m.F);
  }
}

TEST(MeshRepair, NonManifoldEdgeIsSplitForAManifoldSurfaceAndKeptForTheEdgeGraph) {
  Mesh m = test::two_spheres_sharing(2);
  RepairedMesh graph = repair_for(m, MeshRequirements::edge_graph());
  EXPECT_FALSE(graph.changed());  // Coulomb needs only the edges: non-manifold is fine

  RepairedMesh r = repair_for(m, MeshRequirements::manifold_surface());
  expect_consistent(m, r);
  MeshDefects d = mesh_defects(r.mesh);
  EXPECT_EQ(d.nonmanifold_edges, 0);
  EXPECT_EQ(d.nonmanifold_vertices, 0);
  // Split at both endpoints, the spheres come apart: the largest (the first, on a tie) is kept whole.
  EXPECT_EQ(d.components, 1);
  EXPECT_EQ(r.mesh.num_vertices(), 162);
  EXPECT_EQ(r.mesh.num_faces(), 320);
  ASSERT_FALSE(r.actions.empty());
  EXPECT_EQ(r.actions[0].what, "non-manifold vertices split into fans");
  EXPECT_EQ(r.actions[0].count, 2);
  EXPECT_NE(r.text.find("non-manifold vertices split into fans 2"), std::string::npos) << r.text;
}

TEST(MeshRepair, SplitKeepsEveryFaceWhenTheSheetsStayConnected) {
  // A pinch vertex only (one component before and after: no component dropped here, so area is kept).
  Mesh m = test::two_spheres_sharing(1);
  MeshRequirements req = MeshRequirements::manifold_surface();
  req.single_component = false;
  RepairedMesh r = repair_for(m, req);
  expect_consistent(m, r);
  EXPECT_EQ(r.mesh.num_faces(), m.num_faces());
  EXPECT_EQ(r.mesh.num_vertices(), m.num_vertices() + 1);
  EXPECT_NEAR(surface_area(r.mesh.V, r.mesh.F), surface_area(m.V, m.F), 1e-12);
  EXPECT_EQ(mesh_defects(r.mesh).nonmanifold_vertices, 0);
  EXPECT_EQ(mesh_defects(r.mesh).components, 2);
}

TEST(MeshRepair, IsolatedVerticesSmallComponentsAndDuplicatesAreDropped) {
  Mesh iso = test::sphere_with_isolated_vertex();
  RepairedMesh a = repair_for(iso, MeshRequirements::edge_graph());
  expect_consistent(iso, a);
  EXPECT_EQ(a.mesh.num_vertices(), iso.num_vertices() - 1);
  ASSERT_EQ(a.actions.size(), 1u);
  EXPECT_EQ(a.actions[0].what, "isolated vertices dropped");
  EXPECT_EQ(a.actions[0].count, 1);

  Mesh two = test::two_components();
  RepairedMesh b = repair_for(two, MeshRequirements::edge_graph());
  expect_consistent(two, b);
  EXPECT_EQ(b.mesh.num_vertices(), 162);
  for (int v : b.vertex_map) EXPECT_LT(v, 162);

  Mesh dup = test::sphere_with_duplicate_face();
  RepairedMesh c = repair_for(dup, MeshRequirements::edge_graph());
  expect_consistent(dup, c);
  EXPECT_EQ(c.mesh.num_faces(), dup.num_faces() - 1);
  EXPECT_EQ(c.actions[0].what, "duplicate faces dropped");
}

TEST(MeshRepair, ZeroAreaFacesAreDroppedForAManifoldSurfaceOnly) {
  Mesh g = grid(4, 3);
  g.F.conservativeResize(g.num_faces() + 1, 3);
  g.F.row(g.num_faces() - 1) << 0, 1, 2;
  EXPECT_FALSE(repair_for(g, MeshRequirements::edge_graph()).changed());
  RepairedMesh r = repair_for(g, MeshRequirements::manifold_surface());
  EXPECT_EQ(r.mesh.num_faces(), g.num_faces() - 1);
  EXPECT_EQ(mesh_defects(r.mesh).zero_area_faces, 0);
}

TEST(MeshRepair, StrictRefusesNamingTheDefect) {
  RepairOptions strict;
  strict.strict = true;
  strict.name = "two.off";
  try {
    repair_for(test::two_components(), MeshRequirements::edge_graph(), strict);
    FAIL() << "accepted";
  } catch (const Error& e) {
    std::string message = e.what();
    EXPECT_NE(message.find("two.off"), std::string::npos) << message;
    EXPECT_NE(message.find("2 components"), std::string::npos) << message;
    EXPECT_NE(message.find("--strict"), std::string::npos) << message;
  }
  try {
    repair_for(test::two_spheres_sharing(2), MeshRequirements::manifold_surface(), strict);
    FAIL() << "accepted";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("non-manifold edge"), std::string::npos) << e.what();
  }
  // Strict and nothing to repair: accepted.
  EXPECT_NO_THROW(repair_for(test::two_spheres_sharing(2), MeshRequirements::edge_graph(), strict));
}

TEST(MeshRepair, TooFewVerticesLeftIsRefused) {
  Mesh m;
  m.V.resize(3, 3);
  m.V << 0, 0, 0, 1, 0, 0, 0, 1, 0;
  m.F.resize(1, 3);
  m.F << 0, 1, 2;
  EXPECT_THROW(repair_for(m, MeshRequirements::edge_graph()), Error);
}

TEST(MeshRepair, ResultsGoBackToTheInputVertices) {
  std::vector<int> map = {0, 2, 2, 3};  // vertex 1 dropped, vertex 2 split
  Points X(4, 3);
  X << 1, 1, 1, 2, 2, 2, 9, 9, 9, 3, 3, 3;
  Points back = to_input_vertices(X, map, 5);
  ASSERT_EQ(back.rows(), 5);
  EXPECT_EQ(back.row(0), Eigen::RowVector3d(1, 1, 1));
  EXPECT_TRUE(back.row(1).array().isNaN().all());
  EXPECT_EQ(back.row(2), Eigen::RowVector3d(2, 2, 2));  // the first copy
  EXPECT_EQ(back.row(3), Eigen::RowVector3d(3, 3, 3));
  EXPECT_TRUE(back.row(4).array().isNaN().all());
  EXPECT_EQ(valid_input_vertices(map, 5), (Eigen::VectorXd(5) << 1, 0, 1, 1, 0).finished());
}

TEST(MeshRepair, DistancesGoBackToTheInputVerticesWithTheNearestCopy) {
  std::vector<int> map = {0, 2, 2, 3};  // vertex 1 dropped, vertex 2 split into repaired 1 and 2
  EXPECT_EQ(repaired_copies(map, 2), (std::vector<int>{1, 2}));
  EXPECT_TRUE(repaired_copies(map, 1).empty());
  Eigen::VectorXd d(4);
  d << 0, 5, 4, 7;
  Eigen::VectorXd back = distances_to_input_vertices(d, map, 5);
  ASSERT_EQ(back.size(), 5);
  EXPECT_EQ(back[0], 0);
  EXPECT_TRUE(std::isnan(back[1]));
  EXPECT_EQ(back[2], 4);  // the nearer copy
  EXPECT_EQ(back[3], 7);
  EXPECT_TRUE(std::isnan(back[4]));

  DistanceMatrix D(4, 4);
  D << 0, 5, 4, 7,  //
      5, 0, 3, 2,   //
      4, 3, 0, 6,   //
      7, 2, 6, 0;
  DistanceMatrix B = distances_to_input_vertices(D, map, 5);
  ASSERT_EQ(B.rows(), 5);
  EXPECT_EQ(B(0, 2), 4);
  EXPECT_EQ(B(2, 0), 4);
  EXPECT_EQ(B(2, 2), 0);  // the copies of one vertex are one point
  EXPECT_EQ(B(2, 3), 2);
  EXPECT_EQ(B(3, 2), 2);
  EXPECT_EQ(B(0, 3), 7);
  for (Index k = 0; k < 5; ++k) {
    EXPECT_TRUE(std::isnan(B(1, k)) && std::isnan(B(k, 1))) << k;
    EXPECT_TRUE(std::isnan(B(4, k)) && std::isnan(B(k, 4))) << k;
  }
}

}  // namespace mesh_repair_test
}  // namespace cshapes
