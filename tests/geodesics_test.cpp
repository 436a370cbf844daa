#include "cshapes/geodesics/geodesics.h"

#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <random>
#include <sstream>

#include "cshapes/support/error.h"
#include "cshapes/mesh/io.h"
#include "cshapes/data/synthetic.h"
#include "tests/test_support.h"

namespace cshapes {
namespace geodesics_test {

Mesh two_spheres() {
  Mesh a = icosphere(2);
  Mesh two;
  two.V.resize(2 * a.num_vertices(), 3);
  two.V << a.V, (a.V.rowwise() + Eigen::RowVector3d(5, 0, 0));
  two.F.resize(2 * a.num_faces(), 3);
  two.F << a.F, (a.F.array() + static_cast<int>(a.num_vertices())).matrix();
  return two;
}

TEST(Geodesics, MethodNames) {
  for (const char* name : {"heat", "heat-cgal", "fmm", "exact", "graph"})
    EXPECT_EQ(to_string(parse_geodesic_method(name)), name);
  EXPECT_THROW(parse_geodesic_method("dijkstra"), Error);
}

// All-pairs by every fast method: symmetric, zero diagonal, finite, close to the single-source rows, and the
// triangle inequality on sampled triples (up to the method's discretisation error, a fraction of an edge).
TEST(Geodesics, AllPairsInvariants) {
  Mesh m = torus(60, 20, 2.0, 0.7);
  const double h = edge_lengths(m.V, mesh_edges(m.F)).mean();
  std::mt19937 rng(5);
  std::uniform_int_distribution<int> pick(0, static_cast<int>(m.num_vertices()) - 1);
  for (GeodesicMethod method : {GeodesicMethod::Heat, GeodesicMethod::HeatCgal, GeodesicMethod::FastMarching,
                                GeodesicMethod::Graph}) {
    GeodesicOptions options;
    options.method = method;
    int progress_calls = 0;
    options.progress = [&](const std::string&, double done, double total) {
      ++progress_calls;
      EXPECT_LE(done, total);
    };
    DistanceMatrix D = all_pairs_geodesics(m, options);
    ASSERT_EQ(D.rows(), m.num_vertices());
    EXPECT_TRUE(D.allFinite()) << to_string(method);
    EXPECT_EQ((D - D.transpose()).cwiseAbs().maxCoeff(), 0.0f) << to_string(method);
    EXPECT_EQ(D.diagonal().cwiseAbs().maxCoeff(), 0.0f);
    EXPECT_GE(D.minCoeff(), 0.0f);
    EXPECT_GT(progress_calls, 0);
    // Row s is the symmetrised single-source result: within the method's asymmetry of it.
    Eigen::VectorXd row = geodesic_distances(m, {17}, options);
    EXPECT_LT((D.col(17).cast<double>() - row).cwiseAbs().maxCoeff(), 0.5 * h) << to_string(method);
    // Exact geodesics satisfy it; an approximation may break it by about its own error, bounded here by
    // half an edge plus 3% of the path length (the accuracy the heat method is held to).
    int violations = 0;
    double worst = 0;
    for (int t = 0; t < 5000; ++t) {
      int i = pick(rng), j = pick(rng), k = pick(rng);
      double excess = D(i, k) - (D(i, j) + D(j, k));
      worst = std::max(worst, excess / (D(i, j) + D(j, k) + h));
      if (excess > 0.5 * h + 0.03 * (D(i, j) + D(j, k))) ++violations;
    }
    EXPECT_EQ(violations, 0) << to_string(method) << " worst relative excess " << worst;
    if (method == GeodesicMethod::Graph) {
      EXPECT_LE(worst, 1e-6);  // exact on its graph
    }
  }
}

TEST(Geodesics, SymmetrizeIsTiledCorrectly) {
  // Sizes around the tile edge (64).
  for (int n : {1, 63, 64, 65, 130}) {
    DistanceMatrix D = DistanceMatrix::Random(n, n);
    DistanceMatrix expected = 0.5f * (D + D.transpose());
    expected.diagonal().setZero();
    symmetrize_distances(D);
    EXPECT_LT((D - expected).cwiseAbs().maxCoeff(), 1e-7f) << n;
  }
}

TEST(Geodesics, DisconnectedMesh) {
  Mesh two = two_spheres();
  const Index half = two.num_vertices() / 2;
  // Single source: infinity on the other sphere, never NaN, for every method.
  for (const char* name : {"heat", "heat-cgal", "fmm", "exact", "graph"}) {
    GeodesicOptions options;
    options.method = parse_geodesic_method(name);
    Eigen::VectorXd d = geodesic_distances(two, {1}, options);
    EXPECT_FALSE(d.hasNaN()) << name;
    EXPECT_TRUE(d.head(half).allFinite()) << name;
    EXPECT_TRUE(d.tail(half).array().isInf().all()) << name;
  }
  // All pairs: refused with the component sizes.
  try {
    all_pairs_geodesics(two);
    FAIL() << "a disconnected mesh was accepted";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("2 connected components"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("keep the largest component"), std::string::npos) << e.what();
  }
}

// A long thin capsule (300 edge lengths, 6 vertices around, faces split: valence-3 vertices, needle and
// obtuse triangles): every method gives finite distances, close to fast marching's (exact is measured in
// heat_method_test). Where CGAL's heat method underflows: a clear error instead of NaN or DBL_MAX.
TEST(Geodesics, LongThinCapsuleFiniteForEveryMethodOrAClearError) {
  CapsuleOptions o;
  o.segments = 6;
  o.radius = 6 / (2 * 3.14159265358979323846);
  o.length = 300;
  const Mesh m = split_faces(capsule(o), 1);
  GeodesicOptions fmm_options;
  fmm_options.method = GeodesicMethod::FastMarching;
  const Eigen::VectorXd reference = geodesic_distances(m, {0}, fmm_options);
  for (const char* name : {"heat", "fmm", "graph"}) {
    GeodesicOptions options;
    options.method = parse_geodesic_method(name);
    Eigen::VectorXd d = geodesic_distances(m, {0}, options);
    ASSERT_TRUE(d.allFinite()) << name;
    // graph is an upper bound, 5-10% long on such triangles; the others within a few percent.
    EXPECT_LT(test::mean_relative_error(d, reference, 3.0), std::string(name) == "graph" ? 0.15 : 0.03)
        << name;
  }
  // CGAL's heat method holds on there, but 1,000 units (4 around) are too long for it: NaN gradients, then
  // DBL_MAX distances (finite, so the check compares with the sum of the edge lengths).
  CapsuleOptions longer;
  longer.segments = 4;
  longer.radius = 4 / (2 * 3.14159265358979323846);
  longer.length = 1000;
  GeodesicOptions cgal;
  cgal.method = GeodesicMethod::HeatCgal;
  try {
    geodesic_distances(capsule(longer), {0}, cgal);
    FAIL() << "CGAL's heat method unexpectedly succeeded: drop this check";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("heat-cgal"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("from vertex 0"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("--method heat"), std::string::npos) << e.what();
  }
  GeodesicOptions ours;
  EXPECT_TRUE(geodesic_distances(capsule(longer), {0}, ours).allFinite());
}

// All pairs where the heat underflows from most sources: a capsule 400 units long with a time step 20 times
// smaller than usual (the heat reaches ~1/√20 as far: ~250 units). Every entry finite, the far pairs close to
// fast marching's.
// Invariant: distances scale with the mesh, for every method at any finite scale. Fast marching returned
// 4% short distances at 1e12 (an absolute tolerance), zeros at 1e-300 and infinities at 1e154, all with
// exit 0. The all-pairs matrix (float32) refuses, naming float32, the scales whose distances it cannot
// hold.
TEST(Geodesics, DistancesScaleWithTheMeshAtAnyFiniteScale) {
  // Jittered: a regular torus has co-circular quads, whose intrinsic Delaunay flips (heat-cgal) go either way
  // by rounding.
  Mesh m = torus(24, 10, 2.0, 0.7);
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> jitter(-0.05, 0.05);
  for (Index i = 0; i < m.V.rows(); ++i)
    for (int c = 0; c < 3; ++c) m.V(i, c) += jitter(rng);
  for (GeodesicMethod method : {GeodesicMethod::Heat, GeodesicMethod::HeatCgal, GeodesicMethod::FastMarching,
                                GeodesicMethod::Exact, GeodesicMethod::Graph}) {
    GeodesicOptions options;
    options.method = method;
    const Eigen::VectorXd reference = geodesic_distances(m, {3}, options);
    const DistanceMatrix all = all_pairs_geodesics(m, options);
    for (double s : {1e-300, 1e-155, 1e-30, 1e-12, 1e-6, 1e6, 1e12, 1e30, 1e154, 1e300}) {
      SCOPED_TRACE(to_string(method) + " at scale " + std::to_string(s));
      const Mesh scaled{m.V * s, m.F};
      const Eigen::VectorXd d = geodesic_distances(scaled, {3}, options);
      ASSERT_TRUE(d.allFinite());
      EXPECT_LE((d / s - reference).cwiseAbs().maxCoeff(), 1e-9 * reference.maxCoeff());
      if (s < 1e-30 || s > 1e30) {
        try {
          all_pairs_geodesics(scaled, options);
          ADD_FAILURE() << "expected a refusal: these distances do not fit in float32";
        } catch (const Error& e) {
          EXPECT_NE(std::string(e.what()).find("float32"), std::string::npos) << e.what();
        }
        continue;
      }
      const DistanceMatrix D = all_pairs_geodesics(scaled, options);
      EXPECT_LE((D.cast<double>() / s - all.cast<double>()).cwiseAbs().maxCoeff(), 1e-6 * all.maxCoeff());
    }
  }
}

TEST(Geodesics, AllPairsBeyondTheHeatsReachAreFinite) {
  CapsuleOptions o;
  o.segments = 4;
  o.radius = 4 / (2 * 3.14159265358979323846);
  o.length = 400;
  const Mesh m = capsule(o);
  GeodesicOptions heat;
  heat.heat_time_factor = 0.05;
  DistanceMatrix D = all_pairs_geodesics(m, heat);
  ASSERT_TRUE(D.allFinite());
  GeodesicOptions fmm;
  fmm.method = GeodesicMethod::FastMarching;
  const int far_end = static_cast<int>(m.num_vertices()) - 1;
  const Eigen::VectorXd reference = geodesic_distances(m, {far_end}, fmm);
  EXPECT_LT(test::mean_relative_error(D.col(far_end).cast<double>(), reference, 5.0), 0.03);
  EXPECT_NEAR(D(0, far_end), reference[0], 0.02 * reference[0]);
}

TEST(Geodesics, RefusesWhatDoesNotFitInMemory) {
  // require_memory is asked for n² floats before anything is allocated: a 2^22-vertex mesh needs 70 TB.
  Mesh huge;
  huge.V = Points::Zero(1 << 22, 3);
  huge.F = Faces::Zero(0, 3);
  try {
    require_memory(distance_matrix_bytes(huge.num_vertices()), "all-pairs geodesics");
    FAIL() << "70 TB accepted";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("GB"), std::string::npos) << e.what();
  }
}

TEST(GeodesicsCli, AllPairsAndOneRow) {
  std::string dir = test::scratch_dir("geodesics_cli");
  write_mesh(dir + "/t.off", torus(24, 10, 2.0, 0.7));
  test::CliResult r =
      test::run_cli("-q geodesics " + dir + "/t.off -o " + dir + "/D.bin --method fmm --json");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.out.find("\"vertices\": 240"), std::string::npos) << r.out;
  DistanceMatrix D = read_distance_matrix(dir + "/D.bin");
  ASSERT_EQ(D.rows(), 240);
  EXPECT_EQ((D - D.transpose()).cwiseAbs().maxCoeff(), 0.0f);

  r = test::run_cli("-q geodesics " + dir + "/t.off --source 5 --csv --method fmm -o " + dir + "/row.csv");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  std::ifstream csv(dir + "/row.csv");
  std::string line;
  std::getline(csv, line);
  EXPECT_EQ(line, "vertex,distance");
  Mesh m = read_mesh(dir + "/t.off");
  GeodesicOptions fmm;
  fmm.method = GeodesicMethod::FastMarching;
  Eigen::VectorXd row = geodesic_distances(m, {5}, fmm);
  int rows = 0;
  while (std::getline(csv, line)) {
    std::istringstream in(line);
    int vertex;
    char comma;
    double distance;
    in >> vertex >> comma >> distance;
    EXPECT_NEAR(distance, row[vertex], 1e-8 * (1 + row[vertex]));
    ++rows;
  }
  EXPECT_EQ(rows, 240);
}

TEST(GeodesicsCli, DisconnectedMeshIsRepairedOrRefusedWithStrict) {
  std::string dir = test::scratch_dir("geodesics_cli_split");
  Mesh two = two_spheres();
  // Make the second sphere smaller so the largest component is well defined.
  two.F.conservativeResize(two.num_faces() - 40, 3);
  write_mesh(dir + "/two.off", two);
  test::CliResult r = test::run_cli("-q geodesics " + dir + "/two.off -o " + dir + "/D.bin --strict");
  EXPECT_NE(r.exit_code, 0);
  EXPECT_NE(r.err.find("components"), std::string::npos) << r.err;
  EXPECT_FALSE(std::ifstream(dir + "/D.bin").good());
  // By default repaired: the largest component kept; the matrix has the input's vertices, NaN rows and
  // columns for those of the dropped component.
  r = test::run_cli("geodesics " + dir + "/two.off -o " + dir + "/D.bin");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.err.find("repaired"), std::string::npos) << r.err;
  const DistanceMatrix D = read_distance_matrix(dir + "/D.bin");
  ASSERT_EQ(D.rows(), two.num_vertices());
  std::vector<bool> dropped(D.rows());
  Index kept = 0;
  for (Index v = 0; v < D.rows(); ++v) {
    dropped[v] = D.row(v).array().isNaN().all();
    kept += !dropped[v];
  }
  for (Index v = 0; v < D.rows(); ++v)
    for (Index w = 0; w < D.rows(); ++w)
      ASSERT_TRUE(dropped[v] || dropped[w] ? std::isnan(D(v, w)) : std::isfinite(D(v, w))) << v << ", " << w;
  EXPECT_EQ(kept, 162);
}

}  // namespace geodesics_test
}  // namespace cshapes
