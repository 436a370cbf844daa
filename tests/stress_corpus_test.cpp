#include "cshapes/data/stress_corpus.h"

#include <gtest/gtest.h>

#include <set>

#include "cshapes/mesh/mesh.h"

namespace cshapes {
namespace stress_corpus_test {

StressCorpusOptions small() {
  StressCorpusOptions o;
  o.min_vertices = 200;
  o.max_vertices = 800;
  return o;
}

std::vector<int> valences(const Mesh& m) {
  std::vector<int> valence(m.num_vertices(), 0);
  const Edges E = mesh_edges(m.F);
  for (Index e = 0; e < E.rows(); ++e) ++valence[E(e, 0)], ++valence[E(e, 1)];
  return valence;
}

double min_face_area(const Mesh& m) {
  double smallest = 1e300;
  for (Index f = 0; f < m.num_faces(); ++f) {
    const Eigen::Vector3d a = m.V.row(m.F(f, 0)), b = m.V.row(m.F(f, 1)), c = m.V.row(m.F(f, 2));
    smallest = std::min(smallest, 0.5 * (b - a).cross(c - a).norm());
  }
  return smallest;
}

TEST(StressCorpus, CasesAreReproducibleAndCycleThroughEveryKind) {
  std::set<StressKind> kinds;
  for (Index i = 0; i < kStressKinds; ++i) kinds.insert(stress_case(5, i, small()).kind);
  EXPECT_EQ(static_cast<int>(kinds.size()), kStressKinds);
  const StressCase a = stress_case(5, 3, small()), b = stress_case(5, 3, small());
  EXPECT_EQ(a.describe(), b.describe());
  EXPECT_NE(stress_case(5, 3, small()).describe(), stress_case(6, 3, small()).describe());
  const Mesh m1 = make_stress_mesh(a, small()), m2 = make_stress_mesh(b, small());
  EXPECT_EQ(m1.V, m2.V);
  EXPECT_EQ(m1.F, m2.F);
}

TEST(StressCorpus, EachKindHasItsDefect) {
  for (Index i = 0; i < kStressKinds; ++i) {
    const StressCase c = stress_case(3, i, small());
    const Mesh m = make_stress_mesh(c, small());
    const MeshInfo info = mesh_info(m);
    SCOPED_TRACE(c.describe());
    EXPECT_EQ(info.components, 1);
    EXPECT_EQ(info.nonmanifold_edges, 0);
    const double h = info.mean_edge_length;
    switch (c.kind) {
      case StressKind::NearDegenerate:
        EXPECT_LT(min_face_area(m), 1e-12 * h * h);
        break;
      case StressKind::Boundary:
        EXPECT_GT(info.boundary_edges, 0);
        break;
      case StressKind::Handles:
        EXPECT_EQ(info.boundary_edges, 0);
        break;
      case StressKind::Flips:
      case StressKind::Splits: {
        const std::vector<int> v = valences(m);
        EXPECT_LE(*std::min_element(v.begin(), v.end()), 4);
        break;
      }
      case StressKind::Tube:
        EXPECT_GT(info.area, 2 * 3.14159 * 20);  // radius 1, at least 20 long (bent or not)
        break;
      default:
        break;
    }
    if (c.kind != StressKind::Boundary) {
      EXPECT_EQ(info.boundary_edges, 0);
    }
  }
}

TEST(StressCorpus, RandomFlipsKeepTheSurfaceClosedAndManifold) {
  Mesh m = make_stress_mesh(stress_case(1, 0, small()), small());  // a plain remesh
  const MeshInfo before = mesh_info(m);
  const Mesh flipped = random_edge_flips(m, 0.5, 9);
  const MeshInfo after = mesh_info(flipped);
  EXPECT_EQ(after.euler_characteristic, before.euler_characteristic);
  EXPECT_EQ(after.boundary_edges, 0);
  EXPECT_EQ(after.nonmanifold_edges, 0);
  EXPECT_EQ(after.edges, before.edges);
  EXPECT_NE(flipped.F, m.F);
  const std::vector<int> v = valences(flipped);
  EXPECT_GE(*std::min_element(v.begin(), v.end()), 3);
}

}  // namespace stress_corpus_test
}  // namespace cshapes
