#include "cshapes/data/synthetic.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <random>

#include "cshapes/support/error.h"
#include "tests/test_support.h"

namespace cshapes {
namespace synthetic_test {

constexpr double kPi = 3.14159265358979323846;

using test::signed_volume;

// Total triangle area.
double area(const Mesh& m) {
  double a = 0;
  for (Index f = 0; f < m.num_faces(); ++f)
    a +=
        0.5 * (m.V.row(m.F(f, 1)) - m.V.row(m.F(f, 0))).cross(m.V.row(m.F(f, 2)) - m.V.row(m.F(f, 0))).norm();
  return a;
}
// Every undirected edge in exactly two faces, once in each direction (closed and consistently oriented).
bool closed_and_oriented(const Mesh& m) {
  std::map<std::pair<int, int>, int> directed;
  for (Index f = 0; f < m.num_faces(); ++f)
    for (int k = 0; k < 3; ++k) ++directed[{m.F(f, k), m.F(f, (k + 1) % 3)}];
  for (const auto& [edge, count] : directed)
    if (count != 1 || directed.count({edge.second, edge.first}) == 0) return false;
  return true;
}

TEST(Synthetic, CapsuleIsAClosedOrientedSphere) {
  for (double bend : {0.0, 2.0}) {
    CapsuleOptions o;
    o.length = 20;
    o.radius = 2;
    o.segments = 16;
    o.bend = bend;
    Mesh m = capsule(o);
    EXPECT_TRUE(closed_and_oriented(m)) << bend;
    const Index edges = 3 * m.num_faces() / 2;
    EXPECT_EQ(m.num_vertices() - edges + m.num_faces(), 2) << bend;  // genus 0
    // Cylinder plus sphere, to the discretisation's error (16 around: a few percent).
    const double volume = kPi * 4 * 20 + 4.0 / 3 * kPi * 8, surface = 2 * kPi * 2 * 20 + 4 * kPi * 4;
    EXPECT_NEAR(signed_volume(m), volume, 0.06 * volume) << bend;
    EXPECT_NEAR(area(m), surface, 0.04 * surface) << bend;
  }
  CapsuleOptions bad;
  bad.segments = 2;
  EXPECT_THROW(capsule(bad), Error);
  bad.segments = 8;
  bad.radius = 0;
  EXPECT_THROW(capsule(bad), Error);
}

TEST(Synthetic, CapsuleRingsAreAboutOneEdgeApart) {
  CapsuleOptions o;
  o.length = 300;
  o.radius = 12 / (2 * kPi);  // ring edge ~1
  o.segments = 12;
  Mesh m = capsule(o);
  EXPECT_NEAR(m.V.col(0).maxCoeff() - m.V.col(0).minCoeff(), 300 + 2 * o.radius, 1e-9);
  // 301 cylinder rings and 2 × 2 cap rings of 12, plus the poles.
  EXPECT_EQ(m.num_vertices(), 12 * (301 + 4) + 2);
}

TEST(Synthetic, SplitFacesAddsValenceThreeVerticesOnTheSurface) {
  Mesh m = icosphere(1);
  Mesh s = split_faces(m, 3);
  const Index splits = (m.num_faces() + 2) / 3;
  EXPECT_EQ(s.num_vertices(), m.num_vertices() + splits);
  EXPECT_EQ(s.num_faces(), m.num_faces() + 2 * splits);
  EXPECT_TRUE(closed_and_oriented(s));
  EXPECT_NEAR(area(s), area(m), 1e-12 * area(m));
  EXPECT_NEAR(signed_volume(s), signed_volume(m), 1e-12);
  std::vector<int> valence(s.num_vertices(), 0);
  for (Index f = 0; f < s.num_faces(); ++f)
    for (int k = 0; k < 3; ++k) ++valence[s.F(f, k)];
  for (Index i = m.num_vertices(); i < s.num_vertices(); ++i) EXPECT_EQ(valence[i], 3);
  EXPECT_THROW(split_faces(m, 0), Error);
  EXPECT_THROW(split_faces(m, 1, 0.7, 0.4), Error);
}

TEST(RandomPoints, DistributionsKnownProperties) {
  std::mt19937_64 rng(3);
  const Points cube = random_points(2000, PointDistribution::Uniform, rng);
  EXPECT_GE(cube.minCoeff(), 0.0);
  EXPECT_LE(cube.maxCoeff(), 1.0);
  // Mean 1/2 per coordinate, standard error 1/sqrt(12·2000) ≈ 0.0065: five of them.
  EXPECT_LT((cube.colwise().mean().array() - 0.5).abs().maxCoeff(), 0.033);
  const Points sphere = random_points(2000, PointDistribution::Sphere, rng);
  EXPECT_LT((sphere.rowwise().norm().array() - 1.0).abs().maxCoeff(), 1e-15);
  EXPECT_LT(sphere.colwise().mean().norm(), 0.1);  // isotropic: mean ≈ 0 (standard error ≈ 0.013 each)
  const Points clusters = random_points(5000, PointDistribution::Clustered, rng);
  EXPECT_TRUE(clusters.allFinite());
  // Clustered: most points have a neighbour far closer than in the uniform cube (mean spacing ~ 0.06).
  int close = 0;
  for (Index i = 0; i < 200; ++i) {
    double nearest = 1e300;
    for (Index j = 0; j < clusters.rows(); ++j)
      if (j != i) nearest = std::min(nearest, (clusters.row(i) - clusters.row(j)).norm());
    close += nearest < 0.01;
  }
  EXPECT_GT(close, 150);
  // The same generator state gives the same points; the generator advances.
  std::mt19937_64 a(9), b(9);
  EXPECT_EQ(random_points(10, PointDistribution::Clustered, a),
            random_points(10, PointDistribution::Clustered, b));
  EXPECT_NE(random_points(10, PointDistribution::Uniform, a),
            random_points(10, PointDistribution::Uniform, rng));
  EXPECT_EQ(parse_point_distribution("sphere"), PointDistribution::Sphere);
  EXPECT_THROW(parse_point_distribution("gaussian"), Error);
}

TEST(SampleSurface, PointsLieOnTheSurfaceUniformlyByArea) {
  // Two triangles in z = 0 of areas 1/2 and 3/2: a quarter of the points in the first.
  Mesh m;
  m.V.resize(4, 3);
  m.V << 0, 0, 0, 1, 0, 0, 0, 1, 0, 0, -3, 0;
  m.F.resize(2, 3);
  m.F << 0, 1, 2, 0, 3, 1;
  std::mt19937_64 rng(4);
  const Points X = sample_surface(m, 20000, rng);
  EXPECT_EQ(X.col(2).cwiseAbs().maxCoeff(), 0.0);
  int first = 0;
  for (Index i = 0; i < X.rows(); ++i) {
    const double x = X(i, 0), y = X(i, 1);
    ASSERT_GE(x, -1e-15);
    if (y >= 0) {
      EXPECT_LE(x + y, 1 + 1e-12);  // inside triangle 0
      ++first;
    } else {
      EXPECT_LE(x - y / 3, 1 + 1e-12);  // inside triangle 1: x + |y|/3 <= 1
    }
  }
  // Binomial standard deviation sqrt(0.25·0.75/20000) ≈ 0.0031: five of them.
  EXPECT_NEAR(first / 20000.0, 0.25, 0.016);
  // On a sphere mesh every sample is between the faces' inradius and the circumradius.
  const Mesh sphere = icosphere(3);
  const Points S = sample_surface(sphere, 1000, rng);
  EXPECT_LE(S.rowwise().norm().maxCoeff(), 1 + 1e-12);
  EXPECT_GE(S.rowwise().norm().minCoeff(), 0.98);
  Mesh flat = m;
  flat.V.col(1).setZero();  // every face degenerate
  EXPECT_THROW(sample_surface(flat, 10, rng), Error);
}

TEST(SwissRollSample, PointsOnTheRollWithExactGeodesics) {
  const SwissRollOptions o;
  const SwissRollSample sample = random_swiss_roll_points(500, 1, o);
  ASSERT_EQ(sample.X.rows(), 500);
  const double length = swiss_roll_length(o.t0, o.t1);
  // One cell of the 4,096-entry angle table, in arc length: the longest is the last (the spiral widens).
  const double cell = swiss_roll_length(o.t1 - (o.t1 - o.t0) / 4096, o.t1);
  for (Index i = 0; i < 500; ++i) {
    const double s = sample.flat(i, 0), y = sample.flat(i, 1);
    ASSERT_GE(s, 0.0);
    ASSERT_LE(s, length);
    ASSERT_GE(y, 0.0);
    ASSERT_LE(y, o.height);
    EXPECT_EQ(sample.X(i, 1), y);
    // The 3-D point is (t cos t, y, t sin t) for a t whose arc length is within 1.5 cells of s (the header's
    // contract: the middle of the cell after the one holding s).
    const double t = std::hypot(sample.X(i, 0), sample.X(i, 2));
    EXPECT_LT(std::abs(std::remainder(std::atan2(sample.X(i, 2), sample.X(i, 0)) - t, 2 * kPi)), 1e-9);
    EXPECT_NEAR(swiss_roll_length(o.t0, t), s, 1.5 * cell);
  }
  const DistanceMatrix D = swiss_roll_geodesic_distances(sample);
  EXPECT_EQ(D.rows(), 500);
  EXPECT_EQ(D.diagonal().cwiseAbs().maxCoeff(), 0.0f);
  EXPECT_EQ((D - D.transpose()).cwiseAbs().maxCoeff(), 0.0f);
  // Geodesic ≥ Euclidean in space (up to the table's placement error and float rounding).
  for (Index i = 0; i < 500; i += 7)
    for (Index j = 0; j < 500; j += 11)
      EXPECT_GE(D(i, j), (sample.X.row(i) - sample.X.row(j)).norm() - 3 * cell - 1e-5 * length);
  // Same seed, same sample.
  EXPECT_EQ(random_swiss_roll_points(50, 7).X, random_swiss_roll_points(50, 7).X);
}

}  // namespace synthetic_test
}  // namespace cshapes
