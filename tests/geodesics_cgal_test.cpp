#include "cshapes/geodesics/geodesics_cgal.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include "cshapes/support/error.h"
#include "cshapes/geodesics/fast_marching.h"
#include "cshapes/geodesics/geodesics.h"
#include "cshapes/geodesics/heat_method.h"
#include "cshapes/mesh/io.h"
#include "cshapes/data/synthetic.h"
#include "tests/test_support.h"

namespace cshapes {
namespace geodesics_cgal_test {

using test::mean_relative_error;

double mean_edge_length(const Mesh& m) {
  return edge_lengths(m.V, mesh_edges(m.F)).mean();
}

TEST(ExactGeodesics, FlatGridIsEuclidean) {
  Mesh m = grid(15, 11, 1.4, 1.0);
  for (int source : {0, 80}) {
    Eigen::VectorXd exact = (m.V.rowwise() - m.V.row(source)).rowwise().norm();
    Eigen::VectorXd d = exact_geodesics(m, {source});
    EXPECT_LT((d - exact).cwiseAbs().maxCoeff(), 1e-9);
  }
  // Several sources: the nearest one.
  Eigen::VectorXd both = exact_geodesics(m, {0, 80});
  Eigen::VectorXd d0 = exact_geodesics(m, {0}), d80 = exact_geodesics(m, {80});
  EXPECT_LT((both - d0.cwiseMin(d80)).cwiseAbs().maxCoeff(), 1e-9);
}

// Issue 36: a stop (Ctrl-C in Python) is heard in the progress function, which all-pairs exact geodesics
// called every 64 sources (8-16 s on 5,000 vertices); now after every source. The stop ends the call at once.
TEST(ExactGeodesics, AllPairsReportsEverySourceAndStops) {
  const Mesh m = grid(8, 6, 1.4, 1.0);  // 48 sources
  GeodesicOptions o;
  o.method = GeodesicMethod::Exact;
  int reports = 0;
  o.progress = [&reports](const std::string&, double, double) { ++reports; };
  all_pairs_geodesics(m, o);
  EXPECT_EQ(reports, m.num_vertices());
  int before_stop = 0;
  o.progress = [&before_stop](const std::string&, double done, double) {
    ++before_stop;
    if (done >= 3) throw Error("stopped");
  };
  EXPECT_THROW(all_pairs_geodesics(m, o), Error);
  EXPECT_LT(before_stop, m.num_vertices());
}

TEST(ExactGeodesics, UnitCubeCornerToCorner) {
  // Opposite corners of a unit cube: the shortest path unfolds two faces, length √5.
  Mesh cube;
  cube.V.resize(8, 3);
  for (int i = 0; i < 8; ++i) cube.V.row(i) << (i & 1), (i >> 1) & 1, (i >> 2) & 1;
  cube.F.resize(12, 3);
  cube.F << 0, 2, 1, 1, 2, 3, 4, 5, 6, 5, 7, 6, 0, 1, 4, 1, 5, 4, 2, 6, 3, 3, 6, 7, 0, 4, 2, 2, 4, 6, 1, 3, 5,
      3, 7, 5;
  Eigen::VectorXd d = exact_geodesics(cube, {0});
  EXPECT_NEAR(d[7], std::sqrt(5.0), 1e-12);
  EXPECT_NEAR(d[3], std::sqrt(2.0), 1e-12);
  EXPECT_NEAR(d[1], 1.0, 1e-12);
}

TEST(CgalHeatMethod, DirectModeMatchesOurHeatMethod) {
  // Same discretisation (cotangent Laplacian, lumped mass, t = h²): equal up to solver rounding on a mesh
  // whose heat solution stays positive (CGAL takes |u|, which differs from u only where obtuse angles make it
  // oscillate).
  Mesh m = torus(48, 24, 2.0, 0.6);
  HeatMethodOptions direct;
  direct.intrinsic_delaunay = false;
  HeatMethod ours(m, direct);
  CgalHeatMethod cgal(m, CgalHeatMode::Direct);
  for (int source : {0, 333, 1000}) {
    Eigen::VectorXd a = ours.distances_each({source}).col(0), b = cgal.distances({source});
    EXPECT_LT((a - b).cwiseAbs().maxCoeff(), 2e-5 * b.maxCoeff()) << "source " << source;
  }
}

TEST(CgalHeatMethod, IntrinsicDelaunayModeMatchesOurHeatMethod) {
  CSHAPES_REQUIRE_DATA();
  Mesh cat = read_mesh(test::tosca5k("cat0"));  // thousands of non-Delaunay edges
  HeatMethod ours(cat);
  EXPECT_GT(ours.intrinsic_flips(), 1000);
  CgalHeatMethod cgal(cat, CgalHeatMode::IntrinsicDelaunay);
  Eigen::VectorXd a = ours.distances_each({0}).col(0), b = cgal.distances({0});
  EXPECT_LT((a - b).cwiseAbs().maxCoeff(), 1e-3 * b.maxCoeff());
}

TEST(CgalHeatMethod, BothModesOnASphere) {
  const double radius = 2.0;
  Mesh m = icosphere(4, radius);
  const double h = mean_edge_length(m);
  for (CgalHeatMode mode : {CgalHeatMode::Direct, CgalHeatMode::IntrinsicDelaunay}) {
    Eigen::VectorXd d = cgal_heat_method(m, {5}, mode);
    Eigen::Vector3d s = m.V.row(5).normalized();
    Eigen::VectorXd exact(m.num_vertices());
    for (Index i = 0; i < m.num_vertices(); ++i)
      exact[i] = radius * std::acos(std::clamp(m.V.row(i).normalized().dot(s), -1.0, 1.0));
    EXPECT_LT(mean_relative_error(d, exact, 3 * h), 0.03) << to_string(mode);
  }
  EXPECT_EQ(parse_cgal_heat_mode("idt"), CgalHeatMode::IntrinsicDelaunay);
  EXPECT_THROW(parse_cgal_heat_mode("cotan"), std::exception);
}

// The curved case: fast marching and both heat methods against exact geodesics on a TOSCA cat (5,000
// vertices) and on a torus (negative and positive curvature).
void check_against_exact(const Mesh& m, const std::vector<int>& sources, double fmm_tolerance,
                         double heat_tolerance, const std::string& name) {
  const double h = mean_edge_length(m);
  FastMarching fmm(m);
  HeatMethod heat(m);
  CgalHeatMethod cgal_idt(m, CgalHeatMode::IntrinsicDelaunay);
  for (int s : sources) {
    Eigen::VectorXd exact = exact_geodesics(m, {s});
    double e_fmm = mean_relative_error(fmm.distances({s}), exact, 3 * h);
    double e_heat = mean_relative_error(heat.distances_each({s}).col(0), exact, 3 * h);
    double e_idt = mean_relative_error(cgal_idt.distances({s}), exact, 3 * h);
    EXPECT_LT(e_fmm, fmm_tolerance) << name << " source " << s;
    EXPECT_LT(e_heat, heat_tolerance) << name << " source " << s;
    EXPECT_LT(e_idt, heat_tolerance) << name << " source " << s;
    std::printf("%s source %d: fmm %.4f heat %.4f idt %.4f\n", name.c_str(), s, e_fmm, e_heat, e_idt);
  }
}

TEST(Geodesics, TorusAgainstExact) {
  check_against_exact(torus(96, 32, 2.0, 0.7), {0, 1000, 1500}, 0.02, 0.03, "torus");
}

TEST(Geodesics, CatAgainstExact) {
  CSHAPES_REQUIRE_DATA();
  Mesh cat = read_mesh(test::tosca5k("cat0"));
  check_against_exact(cat, {0, 2500}, 0.02, 0.03, "cat0");
}

}  // namespace geodesics_cgal_test
}  // namespace cshapes
