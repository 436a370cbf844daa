#include "cshapes/geodesics/fast_marching.h"

#include <gtest/gtest.h>

#include "tests/test_support.h"

#include <cmath>
#include <random>

#include "cshapes/data/synthetic.h"

namespace cshapes {
namespace fast_marching_test {

using test::mean_relative_error;

// A flat grid with every interior vertex moved in the plane by up to `jitter` spacings: irregular triangles
// (some obtuse), while distances stay Euclidean.
Mesh jittered_grid(int n, double jitter, unsigned seed) {
  Mesh m = grid(n, n, 1.0, 1.0);
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(-jitter / (n - 1), jitter / (n - 1));
  for (Index i = 0; i < m.num_vertices(); ++i) {
    double x = m.V(i, 0), y = m.V(i, 1);
    if (x > 0 && x < 1 && y > 0 && y < 1) m.V(i, 0) += u(rng), m.V(i, 1) += u(rng);
  }
  return m;
}

using test::obtuse_grid;

Eigen::VectorXd euclidean_from(const Mesh& m, int source) {
  return (m.V.rowwise() - m.V.row(source)).rowwise().norm();
}

TEST(FastMarching, FlatJitteredGridIsEuclidean) {
  const int n = 121;
  Mesh m = jittered_grid(n, 0.3, 7);
  const double h = 1.0 / (n - 1);
  FastMarching fmm(m);
  EXPECT_GT(fmm.obtuse_corners(), 0);
  for (int source : {n * n / 2, 0, 5 * n + 17}) {
    Eigen::VectorXd d = fmm.distances({source});
    EXPECT_EQ(d[source], 0.0);
    double err = mean_relative_error(d, euclidean_from(m, source), 4 * h);
    EXPECT_LT(err, 0.01) << "source " << source;
    // A path along the surface is never shorter than the straight line (up to rounding).
    EXPECT_GE((d - euclidean_from(m, source)).minCoeff(), -1e-9);
  }
}

TEST(FastMarching, SphereGreatCircles) {
  const double radius = 2.0;
  Mesh m = icosphere(5, radius);  // 10,242 vertices
  FastMarching fmm(m);
  const double h = radius * 0.04;  // about the icosphere(5) edge length
  for (int source : {0, 100, 1234}) {
    Eigen::VectorXd d = fmm.distances({source});
    Eigen::VectorXd exact(m.num_vertices());
    Eigen::Vector3d s = m.V.row(source).normalized();
    for (Index i = 0; i < m.num_vertices(); ++i)
      exact[i] = radius * std::acos(std::clamp(m.V.row(i).normalized().dot(s), -1.0, 1.0));
    EXPECT_LT(mean_relative_error(d, exact, 3 * h), 0.01) << "source " << source;
  }
}

TEST(FastMarching, UnfoldingFixesObtuseTriangles) {
  Mesh m = obtuse_grid(61, 121);
  const double h = 1.0 / 60;
  FastMarching unfolded(m);
  FastMarchingOptions no_unfold;
  no_unfold.unfold_obtuse = false;
  FastMarching plain(m, no_unfold);
  EXPECT_GT(unfolded.obtuse_corners(), m.num_faces() / 2);
  EXPECT_GT(unfolded.split_corners(), unfolded.obtuse_corners() / 2);
  EXPECT_EQ(plain.split_corners(), 0);
  const int source = 60 * 61 + 30;  // near the middle
  Eigen::VectorXd exact = euclidean_from(m, source);
  double err_unfolded = mean_relative_error(unfolded.distances({source}), exact, 4 * h);
  double err_plain = mean_relative_error(plain.distances({source}), exact, 4 * h);
  EXPECT_LT(err_unfolded, 0.01);
  EXPECT_LT(err_unfolded, 0.5 * err_plain);
}

TEST(FastMarching, SeveralSourcesAndUnreachableVertices) {
  Mesh a = grid(21, 21);
  Mesh two;  // two copies side by side, not connected
  two.V.resize(2 * a.num_vertices(), 3);
  two.V << a.V, (a.V.rowwise() + Eigen::RowVector3d(2, 0, 0));
  two.F.resize(2 * a.num_faces(), 3);
  two.F << a.F, (a.F.array() + static_cast<int>(a.num_vertices())).matrix();
  Eigen::VectorXd d = fast_marching(two, {0, 20});
  for (Index i = a.num_vertices(); i < two.num_vertices(); ++i) EXPECT_TRUE(std::isinf(d[i]));
  EXPECT_EQ(d[0], 0.0);
  EXPECT_EQ(d[20], 0.0);
  // Two sources: nowhere farther than from either one alone.
  Eigen::VectorXd d0 = fast_marching(a, {0}), d20 = fast_marching(a, {20});
  for (Index i = 0; i < a.num_vertices(); ++i) EXPECT_LE(d[i], std::min(d0[i], d20[i]) + 1e-12);
  EXPECT_THROW(fast_marching(a, {-1}), std::exception);
}

// Continuing a field known on part of the mesh: known values untouched, the rest as close to a full march
// as the first-order scheme allows, unreachable components at infinity.
TEST(FastMarching, ContinuesAPartialField) {
  Mesh a = jittered_grid(41, 0.3, 11);
  Mesh two;  // the grid and a copy beside it, not connected
  two.V.resize(2 * a.num_vertices(), 3);
  two.V << a.V, (a.V.rowwise() + Eigen::RowVector3d(2, 0, 0));
  two.F.resize(2 * a.num_faces(), 3);
  two.F << a.F, (a.F.array() + static_cast<int>(a.num_vertices())).matrix();
  FastMarching fmm(two);
  const int source = 20 * 41 + 3;  // near the left edge, half way up
  Eigen::VectorXd full = fmm.distances({source});
  const Eigen::VectorXd exact = euclidean_from(two, source);
  // Known: the exact distances left of x = 0.3 (a front crossing the grid), unknown elsewhere.
  std::vector<char> known(two.num_vertices(), 0);
  Eigen::VectorXd d = Eigen::VectorXd::Constant(two.num_vertices(), 123.0);  // garbage where unknown
  for (Index i = 0; i < a.num_vertices(); ++i)
    if (two.V(i, 0) < 0.3) known[i] = 1, d[i] = exact[i];
  fmm.continue_distances(d, known);
  for (Index i = 0; i < a.num_vertices(); ++i) {
    if (known[i]) { EXPECT_EQ(d[i], exact[i]); }
  }
  for (Index i = a.num_vertices(); i < two.num_vertices(); ++i) EXPECT_TRUE(std::isinf(d[i]));
  const Eigen::VectorXd part = d.head(a.num_vertices()), full_part = full.head(a.num_vertices()),
                        exact_part = exact.head(a.num_vertices());
  ASSERT_TRUE(part.allFinite());
  // Seeded with exact values, the continuation is at least as accurate as marching from the source.
  EXPECT_LT(mean_relative_error(part, exact_part, 0.1), 0.01);
  EXPECT_LE(mean_relative_error(part, exact_part, 0.1),
            mean_relative_error(full_part, exact_part, 0.1) + 1e-3);
  // Everything known: nothing changes. Bad sizes and non-finite known values are refused.
  std::vector<char> all(two.num_vertices(), 1);
  Eigen::VectorXd same = full.head(a.num_vertices());
  FastMarching fa(a);
  fa.continue_distances(same, std::vector<char>(a.num_vertices(), 1));
  EXPECT_EQ(same, full.head(a.num_vertices()));
  Eigen::VectorXd short_field(3);
  EXPECT_THROW(fmm.continue_distances(short_field, all), std::exception);
  Eigen::VectorXd with_inf = full;  // the copy's vertices are infinite
  EXPECT_THROW(fmm.continue_distances(with_inf, all), std::exception);
}

}  // namespace fast_marching_test
}  // namespace cshapes
