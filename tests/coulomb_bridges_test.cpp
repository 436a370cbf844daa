// Bridges among the torn edges (canon/coulomb_bridges.h) and the Coulomb iteration's second run from the
// start made without them (CoulombCanonOptions::bridge_detour).
#include "cshapes/canon/coulomb_bridges.h"

#include <gtest/gtest.h>

#include <set>
#include <utility>

#include "cshapes/canon/coulomb.h"
#include "cshapes/data/topological_noise.h"
#include "cshapes/mesh/mesh.h"
#include "cshapes/mesh/rigid_transform.h"
#include "tests/test_support.h"

namespace cshapes {
namespace coulomb_bridges_test {

// A flat grid of 40 × 10 vertices, spacing 1, each square split by its diagonal from (i, j) to (i+1, j+1),
// plus one edge from (0, 0) to (39, 0): the edge a glue would add, 39 long. The median edge is 1.
struct Grid {
  static constexpr int kWidth = 40, kHeight = 10;
  Points V;
  Edges E;
  Index glue = -1;
  static Index vertex(int i, int j) { return j * kWidth + i; }
  Index edge(Index a, Index b) const {
    for (Index e = 0; e < E.rows(); ++e)
      if ((E(e, 0) == a && E(e, 1) == b) || (E(e, 0) == b && E(e, 1) == a)) return e;
    return -1;
  }
};

Grid grid_with_a_glue() {
  Grid g;
  g.V.resize(Grid::kWidth * Grid::kHeight, 3);
  std::vector<std::pair<Index, Index>> edges;
  for (int j = 0; j < Grid::kHeight; ++j)
    for (int i = 0; i < Grid::kWidth; ++i) {
      g.V.row(Grid::vertex(i, j)) << i, j, 0;
      if (i + 1 < Grid::kWidth) edges.push_back({Grid::vertex(i, j), Grid::vertex(i + 1, j)});
      if (j + 1 < Grid::kHeight) edges.push_back({Grid::vertex(i, j), Grid::vertex(i, j + 1)});
      if (i + 1 < Grid::kWidth && j + 1 < Grid::kHeight)
        edges.push_back({Grid::vertex(i, j), Grid::vertex(i + 1, j + 1)});
    }
  g.glue = static_cast<Index>(edges.size());
  edges.push_back({Grid::vertex(0, 0), Grid::vertex(Grid::kWidth - 1, 0)});
  g.E.resize(static_cast<Index>(edges.size()), 2);
  for (size_t k = 0; k < edges.size(); ++k) g.E.row(static_cast<Index>(k)) << edges[k].first, edges[k].second;
  return g;
}

// The 11 edges crossing the line x = 20.5 between y = 2 and y = 7: the horizontal ones at y = 2..7 and the
// diagonals between them. Consecutive ones share a vertex: one crack, as tearing opens it.
std::vector<Index> crack_across(const Grid& g) {
  std::vector<Index> crack;
  for (int j = 2; j <= 7; ++j) {
    crack.push_back(g.edge(Grid::vertex(20, j), Grid::vertex(21, j)));
    if (j < 7) crack.push_back(g.edge(Grid::vertex(20, j), Grid::vertex(21, j + 1)));
  }
  return crack;
}

TEST(CoulombBridges, AGlueIsABridge) {
  const Grid g = grid_with_a_glue();
  // The glue's ends are 39 apart along the bottom row, its crack the glue alone (k = 1).
  EXPECT_EQ(torn_bridges(g.V, g.E, {g.glue}, 38.9), std::vector<Index>{g.glue});
  EXPECT_TRUE(torn_bridges(g.V, g.E, {g.glue}, 39.1).empty());
  // Torn with the crack, which it does not touch: still a bridge, and no crack edge is.
  std::vector<Index> torn = crack_across(g);
  torn.push_back(g.glue);
  EXPECT_EQ(torn_bridges(g.V, g.E, torn, 5.0), std::vector<Index>{g.glue});
  EXPECT_THROW(torn_bridges(g.V, g.E, torn, 0.0), Error);
  EXPECT_THROW(torn_bridges(g.V, g.E, {g.E.rows()}, 1.0), Error);
}

TEST(CoulombBridges, ACrackIsNotABridgeNorIsALoneTornEdge) {
  const Grid g = grid_with_a_glue();
  const std::vector<Index> crack = crack_across(g);
  ASSERT_EQ(crack.size(), 11u);
  // Round the crack, the ends of its middle edge (y = 4) are 7 apart (down to y = 1, across, up): beyond
  // min_detour 5, but not beyond the crack's 11 edges.
  EXPECT_TRUE(torn_bridges(g.V, g.E, crack, 5.0).empty());
  EXPECT_TRUE(torn_bridges(g.V, g.E, crack, 0.5).empty());
  // One edge torn alone: its ends are a triangle's other two sides apart (1 + √2), more than its crack of
  // one edge, and more than a small min_detour; no bridge, since a bridge must exceed kMinBridgeDetourEdges.
  const Index lone = g.edge(Grid::vertex(5, 5), Grid::vertex(6, 5));
  EXPECT_TRUE(torn_bridges(g.V, g.E, {lone}, 0.5).empty());
}

// The floor of kMinBridgeDetourEdges median edges: a glue whose ends lie 5 apart along the surface is no
// bridge however small min_detour, one 7 apart is.
TEST(CoulombBridges, ABridgeIsLongerThanSixEdges) {
  Grid g = grid_with_a_glue();
  ASSERT_EQ(kMinBridgeDetourEdges, 6);
  g.E(g.glue, 1) = Grid::vertex(5, 0);
  EXPECT_TRUE(torn_bridges(g.V, g.E, {g.glue}, 0.5).empty());
  g.E(g.glue, 1) = Grid::vertex(7, 0);
  EXPECT_EQ(torn_bridges(g.V, g.E, {g.glue}, 0.5), std::vector<Index>{g.glue});
}

double pose_rms(const Points& A, const Points& B) {
  return aligned_rms(A, B, /*allow_reflection=*/true) / bbox_diagonal(B);
}

// The sausage bent into a C with its ends glued into a ring: torn after the form has settled with the tube
// in it, the glued form stays a few % of the diagonal from the clean sausage's (2.6% when written); started
// again without the tube, it is the clean form up to the iteration's tolerance.
TEST(CoulombBridges, AGluedPoseEndsAtItsCleanPosesFormWhenStartedAgainWithoutTheTube) {
  const Mesh clean = test::bent_sausage(0.15);
  TopologicalNoiseOptions glue;
  glue.glue_count = 1;
  const TopologicalNoiseResult glued = glue_topological_noise(clean, glue);
  std::set<std::pair<Index, Index>> tube;
  for (int a : glued.pairs[0].rim_a)
    for (int b : glued.pairs[0].rim_b) tube.insert({std::min(a, b), std::max(a, b)});

  CoulombCanonOptions o;  // bridge_detour 0.1, the default
  ASSERT_GT(o.bridge_detour, 0);
  const CoulombCanonResult clean_form = coulomb_canonical_form(clean.V, mesh_edges(clean.F), o);
  EXPECT_EQ(clean_form.start.find("bridge"), std::string::npos) << "no glue, no bridge: " << clean_form.start;
  const Edges E = mesh_edges(glued.mesh.F);
  const CoulombCanonResult again = coulomb_canonical_form(glued.mesh.V, E, o);
  ASSERT_NE(again.start.find("bridge"), std::string::npos) << again.start;
  o.bridge_detour = 0;
  const CoulombCanonResult kept = coulomb_canonical_form(glued.mesh.V, E, o);
  // The clean sausage tears no bridge: the option changes nothing there.
  const CoulombCanonResult clean_kept = coulomb_canonical_form(clean.V, mesh_edges(clean.F), o);
  EXPECT_EQ(clean_kept.X, clean_form.X);
  // The tube is torn, and the first run's iterations are in the history.
  int tube_torn = 0;
  for (Index k = 0; k < again.torn_edges.rows(); ++k) {
    const Index a = again.torn_edges(k, 0), b = again.torn_edges(k, 1);
    tube_torn += tube.count({std::min(a, b), std::max(a, b)}) > 0;
  }
  EXPECT_GT(tube_torn, 0);
  EXPECT_EQ(static_cast<int>(again.history.size()), again.iterations);
  EXPECT_GT(again.iterations, kept.iterations);
  const double before = pose_rms(kept.X, clean_form.X), after = pose_rms(again.X, clean_form.X);
  EXPECT_LT(after, 0.5 * before) << "glued vs clean form: " << after << ", without the second run " << before;
}

}  // namespace coulomb_bridges_test
}  // namespace cshapes
