#include "core/fast_marching.h"

#include <gtest/gtest.h>

#include "tests/test_support.h"

#include <cmath>
#include <random>

#include "core/synthetic.h"

namespace cshapes {
namespace {

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

}  // namespace
}  // namespace cshapes
