#include "cshapes/data/topological_noise.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <nlohmann/json.hpp>
#include <set>

#include "cshapes/support/atomic_file.h"
#include "cshapes/support/error.h"
#include "cshapes/mesh/io.h"
#include "cshapes/mesh/remesh.h"
#include "cshapes/data/synthetic.h"
#include "tests/test_support.h"

namespace cshapes {
namespace topological_noise_test {

constexpr double kPi = 3.14159265358979323846;

// Every directed edge at most once: the faces are consistently oriented.
bool consistently_oriented(const Faces& F) {
  std::set<std::pair<int, int>> halfedges;
  for (Index f = 0; f < F.rows(); ++f)
    for (int k = 0; k < 3; ++k)
      if (!halfedges.insert({F(f, k), F(f, (k + 1) % 3)}).second) return false;
  return true;
}

void expect_glued_correctly(const Mesh& input, const TopologicalNoiseResult& r,
                            const TopologicalNoiseOptions& o) {
  MeshInfo before = mesh_info(input), after = mesh_info(r.mesh);
  const long k = static_cast<long>(o.glue_count);
  ASSERT_EQ(static_cast<long>(r.pairs.size()), k);
  EXPECT_EQ(after.euler_characteristic, before.euler_characteristic - 2 * k);
  EXPECT_EQ(after.genus, before.genus + k);
  EXPECT_EQ(after.components, 1);
  EXPECT_EQ(after.nonmanifold_edges, 0);
  EXPECT_EQ(after.boundary_edges, before.boundary_edges);
  EXPECT_EQ(after.vertices, before.vertices);
  EXPECT_TRUE(consistently_oriented(r.mesh.F));
  EXPECT_NO_THROW(validate_mesh(r.mesh, "glued"));
  EXPECT_TRUE(r.mesh.V == input.V);  // vertex positions and order unchanged
  // Thresholds, re-measured independently on the input (exact distances on the glued mesh can only be shorter;
  // the heat method's are within its 3% accuracy contract, tests/heat_method_test.cpp).
  for (const GluedPair& p : r.pairs) {
    double euclidean = (input.V.row(p.a) - input.V.row(p.b)).norm();
    EXPECT_NEAR(euclidean, p.euclidean, 1e-12 * r.mean_edge_length);
    EXPECT_LE(euclidean, r.max_gap);
    double geodesic = geodesic_distances(input, {p.a}, o.geodesic)[p.b];
    const double approximation = o.geodesic.method == GeodesicMethod::Graph ? 1e-9 : 0.03;
    EXPECT_GE(geodesic, p.geodesic * (1 - approximation) - 1e-9 * r.mean_edge_length);
    EXPECT_GE(p.geodesic, o.min_ratio * euclidean);
    EXPECT_GE(p.geodesic, o.min_geodesic_fraction * r.geodesic_diameter);
  }
}

TEST(TopologicalNoise, BentSausageEndsAreGluedIntoATorus) {
  Mesh m = test::bent_sausage(0.15);
  TopologicalNoiseOptions o;
  o.glue_count = 1;
  TopologicalNoiseResult r = glue_topological_noise(m, o);
  expect_glued_correctly(m, r, o);
  // Known answer: the glued spots are the two ends (the vertices nearest angle ±(π - gap/2)).
  for (int v : {r.pairs[0].a, r.pairs[0].b}) EXPECT_GT(std::abs(std::atan2(m.V(v, 1), m.V(v, 0))), 0.8 * kPi);
}

TEST(TopologicalNoise, RefusesWhenNoPairQualifiesAndSaysSo) {
  TopologicalNoiseOptions o;
  o.glue_count = 1;
  try {
    glue_topological_noise(icosphere(3), o);  // convex: no two spots face each other across a gap
    FAIL() << "a sphere has no admissible pair";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("found only 0 of 1 admissible pairs"), std::string::npos)
        << e.what();
  }
  // The sausage has one almost-touching place; twenty glues, kept at least two gaps apart, cannot fit there.
  o.glue_count = 20;
  EXPECT_THROW(glue_topological_noise(test::bent_sausage(0.15), o), Error);
}

// Bridges (edges, not faces) at the sausage's one almost-touching place; the first is the closest pair that
// qualifies, found here by brute force (Dijkstra from every vertex).
TEST(GlueBridges, BentSausageBridgesTheEndsAndTheFirstIsTheClosestQualifyingPair) {
  const Mesh m = test::bent_sausage(0.15);
  const Edges E = mesh_edges(m.F);
  const Eigen::VectorXd lengths = edge_lengths(m.V, E);
  const double h = lengths.mean();
  const Adjacency adj = adjacency(m.num_vertices(), E);
  const Edges bridges = glue_bridges(m.V, E, 3);
  ASSERT_GE(bridges.rows(), 1);
  ASSERT_LE(bridges.rows(), 3);
  std::set<int> ends;
  double previous = 0;
  for (Index k = 0; k < bridges.rows(); ++k) {
    const int i = bridges(k, 0), j = bridges(k, 1);
    EXPECT_LT(i, j);
    EXPECT_TRUE(ends.insert(i).second && ends.insert(j).second) << "each vertex in one bridge at most";
    const double euclidean = (m.V.row(i) - m.V.row(j)).norm();
    EXPECT_LT(euclidean, 8 * h);
    EXPECT_GE(euclidean, previous);  // by increasing length
    previous = euclidean;
    EXPECT_GE(dijkstra(m.num_vertices(), adj, lengths, {i})(j), 15 * h);
    for (int v : {i, j}) EXPECT_GT(std::abs(std::atan2(m.V(v, 1), m.V(v, 0))), 0.8 * kPi);
  }
  double closest = 1e300;
  for (Index i = 0; i < m.num_vertices(); ++i) {
    const Eigen::VectorXd graph = dijkstra(m.num_vertices(), adj, lengths, {static_cast<int>(i)});
    for (Index j = i + 1; j < m.num_vertices(); ++j) {
      const double d = (m.V.row(i) - m.V.row(j)).norm();
      if (d < 8 * h && graph(j) >= 15 * h) closest = std::min(closest, d);
    }
  }
  EXPECT_DOUBLE_EQ((m.V.row(bridges(0, 0)) - m.V.row(bridges(0, 1))).norm(), closest);
  // A convex surface has no such pair.
  const Mesh sphere = icosphere(3);
  EXPECT_THROW(glue_bridges(sphere.V, mesh_edges(sphere.F), 1), Error);
}

TEST(TopologicalNoise, SameSeedSameGlue) {
  Mesh m = test::bent_sausage(0.15);
  TopologicalNoiseOptions o;
  o.seed = 7;
  TopologicalNoiseResult a = glue_topological_noise(m, o), b = glue_topological_noise(m, o);
  EXPECT_TRUE(a.mesh.F == b.mesh.F);
}

TEST(TopologicalNoise, Tosca5kCatGetsTwoHandles) {
  CSHAPES_REQUIRE_DATA();
  Mesh cat = read_mesh(test::tosca5k("cat0"));
  TopologicalNoiseOptions o;
  o.glue_count = 2;
  TopologicalNoiseResult r = glue_topological_noise(cat, o);
  expect_glued_correctly(cat, r, o);
  // Spread: the two glued spots are far apart on the surface.
  Eigen::VectorXd d = geodesic_distances(cat, {r.pairs[0].a, r.pairs[0].b}, o.geodesic);
  EXPECT_GT(std::min(d[r.pairs[1].a], d[r.pairs[1].b]), 2 * r.max_gap);
}

TEST(TopologicalNoise, CliNoiseThenInfoShowsChiMinusTwo) {
  CSHAPES_REQUIRE_DATA();
  std::string dir = test::scratch_dir("noise_cli");
  auto r = test::run_cli("-q noise " + test::tosca5k("cat0") + " -o " + dir +
                         "/n.off --glue 2 --pairs-json " + dir + "/p.json");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  auto info = test::run_cli("info --json " + dir + "/n.off");
  ASSERT_EQ(info.exit_code, 0) << info.err;
  auto j = nlohmann::json::parse(info.out);
  EXPECT_EQ(j["euler_characteristic"], -2);
  EXPECT_EQ(j["components"], 1);
  auto pairs = nlohmann::json::parse(read_file(dir + "/p.json"));
  EXPECT_EQ(pairs["pairs"].size(), 2u);
}

}  // namespace topological_noise_test
}  // namespace cshapes
