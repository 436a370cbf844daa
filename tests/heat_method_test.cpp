#include "cshapes/geodesics/heat_method.h"

#include <gtest/gtest.h>

#include "tests/test_support.h"

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <random>

#include "cshapes/geodesics/fast_marching.h"
#include "cshapes/geodesics/geodesics.h"
#include "cshapes/geodesics/geodesics_cgal.h"
#include "cshapes/mesh/io.h"
#include "cshapes/data/synthetic.h"

namespace cshapes {
namespace heat_method_test {

using test::mean_relative_error;

Eigen::VectorXd great_circle(const Mesh& m, int source, double radius) {
  Eigen::VectorXd exact(m.num_vertices());
  Eigen::Vector3d s = m.V.row(source).normalized();
  for (Index i = 0; i < m.num_vertices(); ++i)
    exact[i] = radius * std::acos(std::clamp(m.V.row(i).normalized().dot(s), -1.0, 1.0));
  return exact;
}

TEST(HeatMethod, FlatGridIsEuclidean) {
  const int n = 81;
  Mesh m = grid(n, n, 2.0, 2.0);
  const double h = 2.0 / (n - 1);
  HeatMethod heat(m);
  EXPECT_NEAR(heat.time_step(), h * h * (2 + std::sqrt(2.0)) / 3 * (2 + std::sqrt(2.0)) / 3, 0.05 * h * h);
  for (int source : {n * n / 2, 0, 10 * n + 30}) {
    Eigen::VectorXd exact = (m.V.rowwise() - m.V.row(source)).rowwise().norm();
    Eigen::VectorXd d = heat.distances({source});
    EXPECT_EQ(d[source], 0.0);
    EXPECT_LT(mean_relative_error(d, exact, 4 * h), 0.03) << "source " << source;
  }
}

TEST(HeatMethod, SphereGreatCircles) {
  const double radius = 3.0;
  Mesh m = icosphere(4, radius);
  HeatMethod heat(m);
  const double h = 0.08 * radius;
  for (int source : {0, 321, 2000}) {
    EXPECT_LT(mean_relative_error(heat.distances({source}), great_circle(m, source, radius), 3 * h), 0.03);
  }
}

TEST(HeatMethod, BlocksMatchOneSourceAtATime) {
  Mesh m = torus(40, 20, 2.0, 0.7);
  HeatMethodOptions options;
  options.block_size = 7;  // several blocks, the last one partial
  HeatMethod heat(m, options);
  std::vector<int> sources = {0, 5, 99, 400, 401, 799, 17, 250, 300, 333, 12, 600, 777, 42, 43, 44, 45};
  Eigen::MatrixXd each = heat.distances_each(sources);
  ASSERT_EQ(each.cols(), static_cast<Index>(sources.size()));
  const double scale = each.maxCoeff();
  for (size_t k = 0; k < sources.size(); ++k) {
    Eigen::VectorXd single = heat.distances({sources[k]});
    EXPECT_LT((each.col(k) - single).cwiseAbs().maxCoeff(), 1e-3 * scale) << "source " << sources[k];
    EXPECT_EQ(each(sources[k], k), 0.0);
    EXPECT_GE(each.col(k).minCoeff(), 0.0);
  }
}

TEST(HeatMethod, ScaleInvariant) {
  // Distances scale with the mesh (the time step is tied to the edge length).
  Mesh m = icosphere(3);
  Mesh big = m, small = m;
  big.V *= 1e4;
  small.V *= 1e-4;
  Eigen::VectorXd d = heat_method(m, {7});
  EXPECT_LT((heat_method(big, {7}) / 1e4 - d).cwiseAbs().maxCoeff(), 1e-8 * d.maxCoeff());
  EXPECT_LT((heat_method(small, {7}) / 1e-4 - d).cwiseAbs().maxCoeff(), 1e-8 * d.maxCoeff());
}

TEST(HeatMethod, DisconnectedMeshGivesInfinityNotNaN) {
  Mesh a = icosphere(2);
  Mesh two;
  two.V.resize(2 * a.num_vertices(), 3);
  two.V << a.V, (a.V.rowwise() + Eigen::RowVector3d(5, 0, 0));
  two.F.resize(2 * a.num_faces(), 3);
  two.F << a.F, (a.F.array() + static_cast<int>(a.num_vertices())).matrix();
  HeatMethod heat(two);
  Eigen::VectorXd d = heat.distances({3});
  Eigen::MatrixXd each = heat.distances_each({3, static_cast<int>(a.num_vertices()) + 3});
  Eigen::VectorXd alone = heat_method(a, {3});
  for (Index i = 0; i < a.num_vertices(); ++i) {
    EXPECT_NEAR(d[i], alone[i], 1e-9);
    EXPECT_TRUE(std::isinf(d[a.num_vertices() + i]));
    EXPECT_TRUE(std::isinf(each(i, 1)));
    EXPECT_NEAR(each(a.num_vertices() + i, 1), alone[i], 1e-9);
  }
  EXPECT_FALSE(d.hasNaN());
  EXPECT_THROW(heat.distances({-1}), std::exception);
  EXPECT_THROW(heat.distances_each({0, static_cast<int>(two.num_vertices())}), std::exception);
}

using test::obtuse_grid;

TEST(HeatMethod, IntrinsicDelaunayRescuesObtuseTriangles) {
  Mesh m = obtuse_grid(41, 81);
  const double h = 1.0 / 40;
  HeatMethod idt(m);
  HeatMethodOptions direct_options;
  direct_options.intrinsic_delaunay = false;
  HeatMethod direct(m, direct_options);
  EXPECT_GT(idt.intrinsic_flips(), 0);
  EXPECT_EQ(direct.intrinsic_flips(), 0);
  const int source = 40 * 41 + 20;
  Eigen::VectorXd exact = (m.V.rowwise() - m.V.row(source)).rowwise().norm();
  const double err_idt = mean_relative_error(idt.distances({source}), exact, 4 * h);
  const double err_direct = mean_relative_error(direct.distances({source}), exact, 4 * h);
  EXPECT_LT(err_idt, 0.03);
  EXPECT_LT(err_idt, 0.5 * err_direct);
}

// A long thin tube: a capsule 6 vertices around (radius 6/2π, so rings one unit apart), `length` units long,
// every face split in three (valence-3 vertices, needle and obtuse triangles), bent by `bend` radians.
Mesh long_thin_tube(double length, double bend) {
  CapsuleOptions o;
  o.segments = 6;
  o.radius = 6 / (2 * 3.14159265358979323846);
  o.length = length;
  o.bend = bend;
  return split_faces(capsule(o), 1);
}

// Relative errors against `exact` over the vertices farther than `min_distance` from the source.
double max_relative_error(const Eigen::VectorXd& d, const Eigen::VectorXd& exact, double min_distance) {
  double worst = 0;
  for (Index i = 0; i < d.size(); ++i)
    if (exact[i] > min_distance) worst = std::max(worst, std::abs(d[i] - exact[i]) / exact[i]);
  return worst;
}

// 300 edge lengths of irregular triangles: the heat decays about twice as fast per unit length as on a
// regular tube. Before the right-hand side was scaled and the gradient normalised without squaring, |∇u|²
// underflowed at ~245 units and the far end got a plateau of finite, wrong distances (18% off at the end).
TEST(HeatMethod, LongThinTubeAgainstExactAtEveryScale) {
  Mesh m = long_thin_tube(300, 3.0);
  const Eigen::VectorXd exact = exact_geodesics(m, {0});
  ASSERT_GT(exact.maxCoeff(), 290);
  for (double scale : {1.0, 1e-8, 1e8}) {
    Mesh scaled = m;
    scaled.V *= scale;
    Eigen::VectorXd d = heat_method(scaled, {0}) / scale;
    ASSERT_TRUE(d.allFinite()) << "scale " << scale;
    EXPECT_LT(mean_relative_error(d, exact, 3.0), 0.02) << "scale " << scale;
    EXPECT_LT(max_relative_error(d, exact, 3.0), 0.04) << "scale " << scale;
  }
}

// Far beyond the heat's reach (2,000 units, ~1,750 mean edge lengths; the heat is trusted to ~1,150 units):
// fast marching continues from the heat-method distances. Reference: fast marching from the source, within
// 0.2% of exact geodesics on this tube (regular triangles, measured at 300 units).
TEST(HeatMethod, ContinuesByFastMarchingWhereTheHeatUnderflows) {
  CapsuleOptions o;
  o.segments = 12;
  o.radius = 12 / (2 * 3.14159265358979323846);
  o.length = 2000;
  Mesh m = capsule(o);
  const int far_end = static_cast<int>(m.num_vertices()) - 1;
  const Eigen::VectorXd reference = fast_marching(m, {0});
  for (double scale : {1.0, 1e-8, 1e8}) {
    Mesh scaled = m;
    scaled.V *= scale;
    HeatMethod heat(scaled);
    Eigen::VectorXd d = heat.distances({0}) / scale;
    ASSERT_TRUE(d.allFinite()) << "scale " << scale;
    EXPECT_EQ(heat.fast_marching_continuations(), 1) << "scale " << scale;
    EXPECT_LT(mean_relative_error(d, reference, 5.0), 0.01) << "scale " << scale;
    EXPECT_LT(max_relative_error(d, reference, 5.0), 0.02) << "scale " << scale;
    EXPECT_NEAR(d[far_end], reference[far_end], 0.01 * reference[far_end]) << "scale " << scale;
  }
  // The block path (for_each_source) continues each column on its own: both poles as sources.
  HeatMethod heat(m);
  Eigen::MatrixXd each = heat.distances_each({0, far_end});
  ASSERT_TRUE(each.allFinite());
  EXPECT_EQ(heat.fast_marching_continuations(), 2);
  EXPECT_LT(max_relative_error(each.col(0), reference, 5.0), 0.02);
  EXPECT_NEAR(each(0, 1), reference[far_end], 0.01 * reference[far_end]);
  // Two sources together: nobody is farther than half the tube.
  Eigen::VectorXd both = heat.distances({0, far_end});
  ASSERT_TRUE(both.allFinite());
  EXPECT_LT(both.maxCoeff(), 0.51 * reference[far_end]);
}

// Short meshes never need the continuation, and give the same distances as before it existed.
TEST(HeatMethod, NoContinuationOnAnOrdinaryMesh) {
  Mesh m = torus(40, 20, 2.0, 0.7);
  HeatMethod heat(m);
  Eigen::MatrixXd each = heat.distances_each({0, 100, 555});
  EXPECT_TRUE(each.allFinite());
  EXPECT_EQ(heat.fast_marching_continuations(), 0);
}

TEST(HeatMethod, WarnsOnCoarseMeshesOnly) {
  Mesh tetrahedron;
  tetrahedron.V.resize(4, 3);
  tetrahedron.V << 1, 1, 1, 1, -1, -1, -1, 1, -1, -1, -1, 1;
  tetrahedron.F.resize(4, 3);
  tetrahedron.F << 0, 1, 2, 0, 3, 1, 0, 2, 3, 1, 3, 2;
  // The heat method is 17% off on average there (CGAL too), where every distance is the edge length.
  const Eigen::VectorXd d = heat_method(tetrahedron, {0});
  EXPECT_GT(std::abs(d[1] - std::sqrt(8.0)) / std::sqrt(8.0), 0.05);
  const std::string warning = heat_method_warning(tetrahedron);
  EXPECT_NE(warning.find("--method exact"), std::string::npos) << warning;
  EXPECT_NE(heat_method_warning(icosphere(1)), "");
  EXPECT_NE(heat_method_warning(torus(20, 10, 1.0, 0.4)), "");  // 200 vertices: 5.9% mean error
  EXPECT_EQ(heat_method_warning(icosphere(4)), "");             // 1.0% mean error
  EXPECT_EQ(heat_method_warning(torus(40, 20, 1.0, 0.4)), "");  // 3.0%
  Mesh big = icosphere(4);
  big.V *= 1e8;
  EXPECT_EQ(heat_method_warning(big), "");
}

// Issue 21's two failures, each on a mesh of the stress corpus that reproduced it with the intrinsic
// Delaunay flips of before (scripts/stress_geodesics.py, seed 1): every distance to one vertex infinite
// (case 164, flips), and a face of the intrinsic triangulation with zero area, all three corners one vertex
// (case 66, splits). Both came from flips of an edge whose two faces share a second edge (a vertex of degree
// 2): the half-edge pairing was rebuilt by slot and corrupted. Every distance must now be finite and close to
// the exact geodesics, from every vertex (all pairs) and against CGAL's exact distances from a few sources.
void expect_heat_matches_exact_on(const Mesh& m, const std::string& file) {
  SCOPED_TRACE(file);
  const DistanceMatrix D = all_pairs_geodesics(m);  // heat; throws on any non-finite distance
  EXPECT_TRUE(D.allFinite());
  const double h = mesh_info(m).mean_edge_length;
  HeatMethod heat(m);
  for (int source : {0, static_cast<int>(m.num_vertices() / 2), static_cast<int>(m.num_vertices() - 1)}) {
    const Eigen::VectorXd exact = exact_geodesics(m, {source});
    const Eigen::VectorXd d = heat.distances({source});
    ASSERT_TRUE(d.allFinite()) << "source " << source;
    EXPECT_LT(mean_relative_error(d, exact, 3 * h), 0.05) << "source " << source;
  }
}

void expect_heat_matches_exact(const std::string& file) {
  expect_heat_matches_exact_on(read_mesh(std::string(CSHAPES_SOURCE_DIR) + "/tests/regressions/" + file),
                               file);
}

// The centaur mesh, written by its generator at test time (deterministic, Python's standard library only).
Mesh centaur_fan_mesh() {
  const std::string dir = test::scratch_dir("centaur-fan"), path = dir + "/centaur_fan.off";
  const std::string command = "python3 '" + std::string(CSHAPES_SOURCE_DIR) +
                              "/tests/regressions/make_centaur_fan_failing.py' '" + path + "'";
  EXPECT_EQ(std::system(command.c_str()), 0) << command;
  Mesh m = read_mesh(path);
  std::filesystem::remove_all(dir);
  return m;
}

TEST(HeatMethod, Issue21InfiniteDistancesToAVertex) {
  expect_heat_matches_exact("idt_inf_vertex_flips332.off");
}

TEST(HeatMethod, Issue21ZeroAreaIntrinsicFace) {
  expect_heat_matches_exact("idt_zero_area_face_splits641.off");
}

// The centaur vertex of issue 21 rebuilt from its four faces' angles and edge lengths, inside a closed
// genus-0 mesh (tests/regressions/make_centaur_fan_failing.py writes it at test time; its header
// has the flip sequence): a valence-4 cone point of 328 degrees with a 131-degree angle. Before the fix,
// every distance to and from the fan's neighbour w0 (vertex 1) was inf ("the distance from vertex 0 to vertex
// 1 is inf"): the flips left w0 with degree 2 and then corrupted the pairing, as on the centaur. Now every
// distance is finite and close to the exact geodesics, and the fan's own vertices are reached from afar.
TEST(HeatMethod, Issue21CentaurValenceFourVertex) {
  const Mesh m = centaur_fan_mesh();
  ASSERT_EQ(m.num_vertices(), 1432);
  expect_heat_matches_exact_on(m, "centaur fan");
  HeatMethod heat(m);
  const int pole = static_cast<int>(m.num_vertices() - 1);
  const Eigen::VectorXd d = heat.distances({pole}), exact = exact_geodesics(m, {pole});
  for (int fan_vertex = 0; fan_vertex <= 4; ++fan_vertex)
    EXPECT_NEAR(d[fan_vertex], exact[fan_vertex], 0.02 * exact[fan_vertex]) << "fan vertex " << fan_vertex;
}

// Degenerate input faces (a corner on the opposite edge, coincident corners) are mollified, in both modes.
TEST(HeatMethod, DegenerateFacesAreAccepted) {
  Mesh m = icosphere(4, 2.0);
  const int a = m.F(0, 0), b = m.F(0, 1), c = m.F(0, 2);
  m.V.row(c) = 0.5 * (m.V.row(a) + m.V.row(b));
  m.V.row(m.F(500, 1)) = m.V.row(m.F(500, 0));
  for (bool idt : {true, false}) {
    HeatMethodOptions options;
    options.intrinsic_delaunay = idt;
    HeatMethod heat(m, options);
    EXPECT_GT(heat.mollification(), 0.0);
    const Eigen::VectorXd d = heat.distances({100});
    ASSERT_TRUE(d.allFinite());
    EXPECT_LT(mean_relative_error(d, great_circle(m, 100, 2.0), 0.3), 0.05) << (idt ? "idt" : "direct");
  }
}

// A stop (Ctrl-C in Python: a progress callback that throws Cancelled, support/progress.h) is heard while the
// heat method factorises, before any source is solved: on a large mesh the set-up is most of a call.
TEST(HeatMethod, AStopIsHeardInTheSetUp) {
  HeatMethodOptions options;
  int calls = 0;
  options.progress = [&](const std::string&, double, double) {
    ++calls;
    throw Cancelled();
  };
  EXPECT_THROW(HeatMethod(torus(40, 20, 2.0, 0.7), options), Cancelled);
  EXPECT_EQ(calls, 1);
}

// Within one block of sources a stop is heard between its solves, not only once the block is finished (one
// block of many sources takes seconds on a large mesh); the first call the callback gets is then a poll.
TEST(HeatMethod, AStopIsHeardWithinABlockOfSources) {
  HeatMethodOptions options;
  options.block_size = 64;  // one block holds every source below
  bool armed = false;
  std::string stage_of_the_stop = "none";
  options.progress = [&](const std::string& stage, double, double) {
    if (!armed) return;
    stage_of_the_stop = stage;
    throw Cancelled();
  };
  const HeatMethod heat(torus(40, 20, 2.0, 0.7), options);
  armed = true;
  std::vector<int> sources;
  for (int s = 0; s < 40; ++s) sources.push_back(s * 20);
  EXPECT_THROW(heat.distances_each(sources), Cancelled);
  EXPECT_EQ(stage_of_the_stop, "");  // a poll, not the report of a finished block
  stage_of_the_stop = "none";
  EXPECT_THROW(heat.distances(sources), Cancelled);  // all sources heated together: polled between solves
  EXPECT_EQ(stage_of_the_stop, "");
}

}  // namespace heat_method_test
}  // namespace cshapes
