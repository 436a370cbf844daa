#include "cshapes/mesh/remesh.h"

#include <gtest/gtest.h>
#include <omp.h>

#include <atomic>
#include <cmath>
#include <thread>
#include <nlohmann/json.hpp>

#include "cshapes/mesh/io.h"
#include "cshapes/data/synthetic.h"
#include "tests/test_support.h"

namespace cshapes {
namespace remesh_test {

void expect_count_within(Index got, Index target, double tolerance) {
  EXPECT_LE(std::abs(static_cast<double>(got - target)), tolerance * static_cast<double>(target))
      << "got " << got << " vertices, target " << target;
}

TEST(Remesh, SphereCoarsenAndRefineHitTheCountAndStayOnTheSphere) {
  Mesh sphere = icosphere(4, 2.0);  // 2,562 vertices
  for (Index target : {1000, 6000}) {
    RemeshOptions o;
    o.target_vertices = target;
    RemeshResult r = remesh(sphere, o);
    MeshInfo info = mesh_info(r.mesh);
    expect_count_within(info.vertices, target, 0.01);
    EXPECT_EQ(info.euler_characteristic, 2);
    EXPECT_EQ(info.components, 1);
    EXPECT_EQ(info.boundary_edges, 0);
    // Known answer: every vertex stays near the sphere of radius 2 (within the sag of the input's chords).
    double sag = 2.0 * (1 - std::cos(info.mean_edge_length / 2.0 / 2.0)) + 2.0 * 1e-3;
    for (Index i = 0; i < r.mesh.num_vertices(); ++i) EXPECT_NEAR(r.mesh.V.row(i).norm(), 2.0, 4 * sag);
    double h = hausdorff_distance(sphere, r.mesh);
    EXPECT_LE(h, 0.01 * info.bbox_diagonal);
    EXPECT_GT(angle_stats(r.mesh).min_angle, 20.0);
  }
}

// Invariant: remeshing commutes with scaling, at any finite scale. 1e100 crashed inside CGAL (SIGSEGV) and
// 1e-100 divided by zero (SIGFPE); the vertex count, the angles and the Hausdorff distance in units of the
// bbox diagonal are those of the unscaled run, within the tolerances of the count and of the sag.
TEST(Remesh, ExtremeScalesGiveTheUnscaledResultScaled) {
  const Mesh sphere = icosphere(3);  // 642 vertices, radius 1
  RemeshOptions o;
  o.target_vertices = 300;
  const RemeshResult unscaled = remesh(sphere, o);
  const double unscaled_h = hausdorff_distance(sphere, unscaled.mesh) / bbox_diagonal(sphere.V);
  const double unscaled_angle = angle_stats(unscaled.mesh).min_angle;
  for (double s : {1e-300, 1e-100, 1e-12, 1e12, 1e100, 1e300}) {
    SCOPED_TRACE(s);
    const Mesh scaled{sphere.V * s, sphere.F};
    const RemeshResult r = remesh(scaled, o);
    expect_count_within(r.mesh.num_vertices(), 300, 0.01);
    ASSERT_TRUE(r.mesh.V.allFinite());
    // Norms in the unscaled units: squares of 1e±300 leave the double range.
    EXPECT_NEAR((r.mesh.V / s).rowwise().norm().maxCoeff(), 1.0, 0.05);
    const double h = hausdorff_distance(scaled, r.mesh) / s / bbox_diagonal(sphere.V);
    EXPECT_NEAR(h, unscaled_h, 0.25 * unscaled_h + 1e-3);
    EXPECT_NEAR(angle_stats(r.mesh).min_angle, unscaled_angle, 5.0);
    EXPECT_NEAR(r.target_edge_length / s, unscaled.target_edge_length, 0.05 * unscaled.target_edge_length);
  }
}

// Measures are scale-free too: the Hausdorff distance scales with the mesh, the angles do not change.
TEST(Remesh, MeasuresHoldAtExtremeScales) {
  Mesh a = grid(5, 5), b = grid(9, 9);
  b.V.col(2).array() += 0.25;
  const AngleStats unit = angle_stats(a);
  for (double s : {1e-150, 1e-100, 1e100, 1e150}) {
    SCOPED_TRACE(s);
    const Mesh as{a.V * s, a.F}, bs{b.V * s, b.F};
    EXPECT_NEAR(hausdorff_distance(as, bs) / s, 0.25, 1e-12);
    EXPECT_NEAR(angle_stats(as).min_angle, unit.min_angle, 1e-9);
    EXPECT_NEAR(angle_stats(as).max_angle, unit.max_angle, 1e-9);
  }
}

TEST(Remesh, OpenSheetKeepsItsBoundaryLoop) {
  Mesh sheet = grid(30, 20, 3.0, 2.0);
  RemeshOptions o;
  o.target_vertices = 900;
  RemeshResult r = remesh(sheet, o);
  MeshInfo info = mesh_info(r.mesh);
  expect_count_within(info.vertices, 900, 0.01);
  EXPECT_EQ(info.euler_characteristic, 1);
  EXPECT_EQ(info.boundary_loops, 1);
  EXPECT_NEAR(info.area, 6.0, 6.0 * 0.01);
}

TEST(Remesh, HausdorffOfBruteForceCases) {
  // Two parallel unit squares 0.25 apart: the Hausdorff distance is exactly 0.25.
  Mesh a = grid(5, 5), b = grid(9, 9);
  b.V.col(2).array() += 0.25;
  EXPECT_NEAR(hausdorff_distance(a, b), 0.25, 1e-12);
  EXPECT_NEAR(hausdorff_distance(a, a), 0.0, 1e-12);
  // A non-manifold mesh (TOPKIDS's kid00 has an edge of four faces) is measured too: a unit square of two
  // triangles with a fin of height 1 standing on their shared diagonal, an edge of three faces. Its apex lies
  // 1 above the flat square, every other sample on it.
  Mesh fin = grid(2, 2);
  Eigen::Vector2i shared(-1, -1);
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j)
      if (fin.F(0, i) == fin.F(1, (j + 1) % 3) && fin.F(0, (i + 1) % 3) == fin.F(1, j))
        shared << fin.F(0, i), fin.F(0, (i + 1) % 3);
  ASSERT_GE(shared[0], 0);
  fin.V.conservativeResize(5, 3);
  fin.V.row(4) = (fin.V.row(shared[0]) + fin.V.row(shared[1])) / 2 + Eigen::RowVector3d(0, 0, 1);
  fin.F.conservativeResize(3, 3);
  fin.F.row(2) << shared[0], shared[1], 4;
  EXPECT_EQ(mesh_info(fin).boundary_edges, 6);  // 4 sides of the square, 2 of the fin
  EXPECT_NEAR(hausdorff_distance(fin, grid(9, 9)), 1.0, 1e-12);
}

TEST(Remesh, AngleStatsOfEquilateralAndRightTriangles) {
  Mesh m;
  m.V.resize(4, 3);
  m.V << 0, 0, 0, 1, 0, 0, 0.5, std::sqrt(3.0) / 2, 0, 0, -1, 0;
  m.F.resize(2, 3);
  m.F << 0, 1, 2, 0, 3, 1;
  AngleStats s = angle_stats(m);
  EXPECT_NEAR(s.min_angle, 45.0, 1e-9);
  EXPECT_NEAR(s.max_angle, 90.0, 1e-9);
  EXPECT_NEAR(s.mean_min_angle, 52.5, 1e-9);
}

TEST(Remesh, TwoSpheresIntersectOneDoesNot) {
  Mesh a = icosphere(2);
  EXPECT_FALSE(self_intersects(a));
  Mesh b = icosphere(2);
  b.V.col(0).array() += 0.5;
  Mesh both;
  both.V.resize(a.V.rows() * 2, 3);
  both.V << a.V, b.V;
  both.F.resize(a.F.rows() * 2, 3);
  both.F << a.F, b.F.array() + static_cast<int>(a.V.rows());
  EXPECT_TRUE(self_intersects(both));
}

TEST(Remesh, Tosca5kCatTo3505WithinOnePercentOfTheDiagonal) {
  CSHAPES_REQUIRE_DATA();
  Mesh cat = read_mesh(test::tosca5k("cat0"));
  RemeshOptions o;
  o.target_vertices = 3505;
  RemeshResult r = remesh(cat, o);
  MeshInfo info = mesh_info(r.mesh);
  expect_count_within(info.vertices, 3505, 0.01);
  EXPECT_EQ(info.euler_characteristic, 2);
  EXPECT_EQ(info.components, 1);
  double h = hausdorff_distance(cat, r.mesh);
  EXPECT_LE(h, 0.01 * info.bbox_diagonal) << "Hausdorff " << h << ", diagonal " << info.bbox_diagonal;
  EXPECT_GE(angle_stats(r.mesh).min_angle, angle_stats(cat).min_angle);
}

// When the plain remesh may miss the Hausdorff goal, it and the first feature-line remesh run side by side on
// two threads: the result, and a failure, must be the ones of a single thread (the runs one after the other).
// A thin lens needs its rim kept as a feature line (the fallback is used); a sphere does not.
TEST(Remesh, SideBySideRunsGiveTheOneThreadResult) {
  Mesh lens = icosphere(4);  // 2,562 vertices
  lens.V.col(2) *= 0.03;
  const int before = omp_get_max_threads();
  auto run = [](const Mesh& mesh, const RemeshOptions& o, int threads) {
    omp_set_num_threads(threads);
    return remesh(mesh, o);
  };
  const Mesh sphere = icosphere(4);
  for (const Mesh* mesh : std::initializer_list<const Mesh*>{&lens, &sphere}) {
    RemeshOptions o;
    o.target_vertices = 400;
    const RemeshResult one = run(*mesh, o, 1), two = run(*mesh, o, 2);
    EXPECT_EQ(one.feature_lines, mesh == &lens);  // the lens takes the fallback, the sphere does not
    EXPECT_EQ(one.mesh.V, two.mesh.V);
    EXPECT_EQ(one.mesh.F, two.mesh.F);
    EXPECT_EQ(one.attempts, two.attempts);
    EXPECT_EQ(one.hausdorff, two.hausdorff);
    EXPECT_EQ(one.feature_lines, two.feature_lines);
    EXPECT_EQ(one.feature_angle_deg, two.feature_angle_deg);
  }
  RemeshOptions failing;
  failing.target_vertices = 400;
  failing.max_attempts = 1;
  failing.tolerance = 1e-6;
  std::string messages[2];
  for (int threads : {1, 2}) {
    try {
      run(lens, failing, threads);
    } catch (const Error& e) {
      messages[threads - 1] = e.what();
    }
  }
  omp_set_num_threads(before);
  EXPECT_NE(messages[0], "");
  EXPECT_EQ(messages[0], messages[1]);
}

// A stop (Ctrl-C) that only the second thread's run hears is still the user's stop: the remesh ends with it,
// even when the plain run, on the other thread, met the goal and its result would do.
TEST(Remesh, AStopHeardBySideBySideRunIsNotLost) {
  const int before = omp_get_max_threads();
  omp_set_num_threads(2);
  const std::thread::id caller = std::this_thread::get_id();
  const Mesh sphere = icosphere(4);
  // Which run the second thread takes is OpenMP's choice: ten tries, so that it is the feature-line run in
  // some (when it is the plain run, its own failure carries the stop).
  for (int attempt = 0; attempt < 10; ++attempt) {
    std::atomic<bool> stopped{false};
    RemeshOptions o;
    o.target_vertices = 400;
    o.progress = [&](const std::string&, double, double) {
      if (std::this_thread::get_id() != caller && !stopped.exchange(true)) throw Cancelled();
    };
    bool cancelled = false;
    try {
      remesh(sphere, o);
    } catch (const Cancelled&) {
      cancelled = true;
    }
    EXPECT_TRUE(stopped.load()) << "try " << attempt;  // the other thread polled
    EXPECT_TRUE(cancelled) << "try " << attempt;
  }
  omp_set_num_threads(before);
}

// The progress line says 100% only as remesh() returns: with one attempt per run and a Hausdorff goal no run
// meets (every feature-line run follows the plain one), every report before the last is below its total,
// and nothing (no report, no poll: no work) comes after the one at 100%.
TEST(Remesh, ProgressReachesItsTotalOnlyAtTheEnd) {
  RemeshOptions o;
  o.target_vertices = 300;
  o.max_attempts = 1;
  o.max_hausdorff_fraction = 1e-9;
  struct Call {
    std::string stage;
    double done, total;
  };
  std::vector<Call> calls;
  o.progress = [&](const std::string& stage, double done, double total) {
    calls.push_back({stage, done, total});
  };
  remesh(icosphere(3), o);
  Index reports = 0;
  for (const Call& c : calls) reports += !c.stage.empty();
  EXPECT_GE(reports, 3);  // the feature-line runs did follow the plain one
  ASSERT_FALSE(calls.empty());
  const Call& last = calls.back();
  EXPECT_EQ(last.stage, "remesh");
  EXPECT_EQ(last.done, last.total);
  double previous = 0;
  for (size_t i = 0; i + 1 < calls.size(); ++i) {
    if (calls[i].stage.empty()) continue;
    EXPECT_LT(calls[i].done, calls[i].total) << "report " << i << " of " << calls.size();
    EXPECT_GE(calls[i].done, previous) << "report " << i;  // never backwards
    previous = calls[i].done;
  }
}

// `cshapes remesh --subdivide K`: the remesh, then K midpoint subdivisions: V + E + F-grown counts exactly
// (V' = V + E, F' = 4F per round, Euler characteristic kept), still on the unit sphere's polyhedron.
TEST(Remesh, CliSubdividesTheRemesh) {
  const std::string dir = test::scratch_dir("remesh_subdivide");
  write_mesh(dir + "/sphere.off", icosphere(3, 1.0));
  const test::CliResult plain =
      test::run_cli("-q remesh " + dir + "/sphere.off -o " + dir + "/r.off --vertices 300 --json");
  ASSERT_EQ(plain.exit_code, 0) << plain.err;
  const test::CliResult twice = test::run_cli("-q remesh " + dir + "/sphere.off -o " + dir +
                                              "/r2.off --vertices 300 --subdivide 2 --json");
  ASSERT_EQ(twice.exit_code, 0) << twice.err;
  const nlohmann::json a = nlohmann::json::parse(plain.out), b = nlohmann::json::parse(twice.out);
  const Mesh r = read_mesh(dir + "/r.off"), r2 = read_mesh(dir + "/r2.off");
  const Index v = r.num_vertices(), f = r.num_faces(), e = v + f - 2;  // closed genus 0: V − E + F = 2
  EXPECT_EQ(b["remeshed_vertices"].get<long>(), v);  // the same remesh (deterministic)
  EXPECT_EQ(b["subdivisions"].get<int>(), 2);
  EXPECT_EQ(r2.num_faces(), 16 * f);
  EXPECT_EQ(r2.num_vertices(), v + e + (2 * e + 3 * f));  // round 1 adds E, round 2 adds E' = 2E + 3F
  EXPECT_EQ(b["euler_characteristic"].get<long>(), a["euler_characteristic"].get<long>());
  EXPECT_EQ(Points(r2.V.topRows(v)), r.V);  // the remesh's vertices come first, unmoved
}

}  // namespace remesh_test
}  // namespace cshapes
