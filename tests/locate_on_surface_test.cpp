// Points located on a surface (mesh/locate_on_surface.h): known answers on one triangle, points on generated
// meshes found where they are, points off the surface against a brute-force search over every face (its own
// point-triangle distance: plane projection, else the nearest side), interpolation invariants.
#include "cshapes/mesh/locate_on_surface.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <random>

#include "cshapes/support/error.h"
#include "cshapes/mesh/mesh.h"
#include "cshapes/data/synthetic.h"

namespace cshapes {
namespace locate_on_surface_test {

// Distance from p to segment [a, b].
double segment_distance(const Eigen::Vector3d& p, const Eigen::Vector3d& a, const Eigen::Vector3d& b) {
  const Eigen::Vector3d ab = b - a;
  const double t = std::clamp((p - a).dot(ab) / ab.squaredNorm(), 0.0, 1.0);
  return (a + t * ab - p).norm();
}

// Distance from p to triangle (a, b, c) of positive area, the second code path: the projection onto the
// triangle's plane when it falls inside (signed sub-areas all ≥ 0), else the nearest of the three sides.
double triangle_distance(const Eigen::Vector3d& p, const Eigen::Vector3d& a, const Eigen::Vector3d& b,
                         const Eigen::Vector3d& c) {
  const Eigen::Vector3d n = (b - a).cross(c - a).normalized();
  const Eigen::Vector3d q = p - n * n.dot(p - a);
  if ((b - a).cross(q - a).dot(n) >= 0 && (c - b).cross(q - b).dot(n) >= 0 &&
      (a - c).cross(q - c).dot(n) >= 0)
    return (p - q).norm();
  return std::min({segment_distance(p, a, b), segment_distance(p, b, c), segment_distance(p, c, a)});
}

double brute_force_distance(const Mesh& m, const Eigen::Vector3d& p) {
  double best = std::numeric_limits<double>::infinity();
  for (Index f = 0; f < m.num_faces(); ++f)
    best = std::min(best, triangle_distance(p, m.V.row(m.F(f, 0)), m.V.row(m.F(f, 1)), m.V.row(m.F(f, 2))));
  return best;
}

// Every location's weights are a convex combination and reproduce its closest point on V.
void expect_consistent(const Mesh& m, const SurfaceLocations& at, double scale) {
  const Eigen::MatrixXd back = interpolate_on_surface(m.F, at, m.V);
  for (Index i = 0; i < at.face.size(); ++i) {
    EXPECT_GE(at.barycentric.row(i).minCoeff(), 0.0) << "point " << i;
    EXPECT_LE(at.barycentric.row(i).maxCoeff(), 1.0) << "point " << i;
    EXPECT_NEAR(at.barycentric.row(i).sum(), 1.0, 1e-12) << "point " << i;
    EXPECT_LT((back.row(i) - at.closest.row(i)).norm(), 1e-12 * scale) << "point " << i;
  }
}

TEST(LocateOnSurface, ClosestPointOnTriangleKnowsEachRegion) {
  const Eigen::Vector3d a(0, 0, 0), b(2, 0, 0), c(0, 2, 0);
  struct Case {
    Eigen::Vector3d p, point, weights;
  };
  const Case cases[] = {
      {{-1, -1, 3}, {0, 0, 0}, {1, 0, 0}},                 // beyond corner a
      {{3, -0.5, 1}, {2, 0, 0}, {0, 1, 0}},                // beyond b
      {{-0.5, 4, -2}, {0, 2, 0}, {0, 0, 1}},               // beyond c
      {{0.5, -1, 1}, {0.5, 0, 0}, {0.75, 0.25, 0}},        // facing side ab
      {{-3, 1.5, 0}, {0, 1.5, 0}, {0.25, 0, 0.75}},        // facing side ca
      {{2, 2, 5}, {1, 1, 0}, {0, 0.5, 0.5}},               // facing side bc
      {{0.5, 0.5, -7}, {0.5, 0.5, 0}, {0.5, 0.25, 0.25}},  // above the face
  };
  for (const Case& k : cases) {
    Eigen::Vector3d w;
    const Eigen::Vector3d q = closest_point_on_triangle(k.p, a, b, c, &w);
    EXPECT_LT((q - k.point).norm(), 1e-15) << k.p.transpose();
    EXPECT_LT((w - k.weights).norm(), 1e-15) << k.p.transpose();
    EXPECT_EQ(q, closest_point_on_triangle(k.p, a, b, c)) << "the weights change nothing";
  }
  // Collinear corners: the closest point of the longest side, weights still summing to 1.
  Eigen::Vector3d w;
  const Eigen::Vector3d q = closest_point_on_triangle({1.5, 1, 0}, {0, 0, 0}, {1, 0, 0}, {2, 0, 0}, &w);
  EXPECT_LT((q - Eigen::Vector3d(1.5, 0, 0)).norm(), 1e-15);
  EXPECT_LT((w - Eigen::Vector3d(0.25, 0, 0.75)).norm(), 1e-15);
}

TEST(LocateOnSurface, PointsOnTheSurfaceAreFoundWhereTheyAre) {
  for (const Mesh& m : {torus(24, 12, 1.0, 0.35), icosphere(3, 2.0)}) {
    const double diagonal = bbox_diagonal(m.V);
    std::mt19937_64 rng(3);
    std::uniform_int_distribution<Index> face(0, m.num_faces() - 1);
    std::uniform_real_distribution<double> unit(0.0, 1.0);
    const Index count = 400;
    Points P(count, 3);
    Eigen::VectorXi faces(count);
    Eigen::MatrixX3d weights(count, 3);
    for (Index i = 0; i < count; ++i) {
      faces[i] = static_cast<int>(face(rng));
      double u = unit(rng), v = unit(rng);
      if (u + v > 1) u = 1 - u, v = 1 - v;
      weights.row(i) << 1 - u - v, u, v;
      P.row(i) = Eigen::RowVector3d::Zero();
      for (int k = 0; k < 3; ++k) P.row(i) += weights(i, k) * m.V.row(m.F(faces[i], k));
    }
    const SurfaceLocations at = locate_on_surface(m.V, m.F, P);
    ASSERT_EQ(at.face.size(), count);
    expect_consistent(m, at, diagonal);
    int same_face = 0;
    for (Index i = 0; i < count; ++i) {
      EXPECT_LT(at.distance[i], 1e-12 * diagonal) << "point " << i;
      EXPECT_LT((at.closest.row(i) - P.row(i)).norm(), 1e-12 * diagonal) << "point " << i;
      if (at.face[i] == faces[i]) {
        ++same_face;
        EXPECT_LT((at.barycentric.row(i) - weights.row(i)).norm(), 1e-9) << "point " << i;
      }
    }
    // Random weights put a point on a shared side almost never: its own face is the only closest one.
    EXPECT_GE(same_face, count - 2);
  }
}

TEST(LocateOnSurface, PointsOffTheSurfaceLandAtTheBruteForceClosestPoint) {
  for (const Mesh& m : {torus(24, 12, 1.0, 0.35), icosphere(2, 1.0)}) {
    const double diagonal = bbox_diagonal(m.V);
    std::mt19937_64 rng(11);
    std::uniform_real_distribution<double> coordinate(-0.75 * diagonal, 0.75 * diagonal);
    std::uniform_real_distribution<double> near(-0.05 * diagonal, 0.05 * diagonal);
    std::uniform_int_distribution<Index> vertex(0, m.num_vertices() - 1);
    const Index count = 300;
    Points P(count, 3);
    for (Index i = 0; i < count; ++i) {
      if (i % 2)  // anywhere in a box around the shape, inside it too
        P.row(i) << coordinate(rng), coordinate(rng), coordinate(rng);
      else  // close to the surface, on either side
        P.row(i) = m.V.row(vertex(rng)) + Eigen::RowVector3d(near(rng), near(rng), near(rng));
    }
    const SurfaceLocator locator(m.V, m.F);
    const SurfaceLocations at = locator.locate(P);
    expect_consistent(m, at, diagonal);
    for (Index i = 0; i < count; ++i) {
      EXPECT_NEAR(at.distance[i], brute_force_distance(m, P.row(i).transpose()), 1e-12 * diagonal)
          << "point " << i;
      EXPECT_NEAR(at.distance[i], (P.row(i) - at.closest.row(i)).norm(), 1e-12 * diagonal);
    }
    // Scale robustness: the same mesh and points scaled by 1e8 and 1e-8 give the same faces and weights.
    for (double scale : {1e8, 1e-8}) {
      const SurfaceLocations scaled = locate_on_surface(m.V * scale, m.F, P * scale);
      for (Index i = 0; i < count; ++i) {
        EXPECT_NEAR(scaled.distance[i], at.distance[i] * scale, 1e-9 * diagonal * scale) << "point " << i;
        if (scaled.face[i] == at.face[i]) {
          EXPECT_LT((scaled.barycentric.row(i) - at.barycentric.row(i)).norm(), 1e-9) << "point " << i;
        }
      }
    }
  }
}

TEST(LocateOnSurface, InterpolationReproducesAffineFieldsAndSkipsZeroWeights) {
  const Mesh m = torus(16, 8, 1.0, 0.4);
  Points P = m.V;
  P.col(0).array() += 0.05;
  P.col(2).array() -= 0.03;
  const SurfaceLocations at = locate_on_surface(m.V, m.F, P);
  // An affine map of the vertices, interpolated, is the same map of the closest points.
  Eigen::Matrix3d A;
  A << 2, 0.5, 0, -1, 1, 3, 0.25, 0, -2;
  const Eigen::RowVector3d t(1, -2, 0.5);
  const Eigen::MatrixXd values = (m.V * A.transpose()).rowwise() + t;
  const Eigen::MatrixXd got = interpolate_on_surface(m.F, at, values);
  const Eigen::MatrixXd expected = (at.closest * A.transpose()).rowwise() + t;
  EXPECT_LT((got - expected).cwiseAbs().maxCoeff(), 1e-12);
  // A vertex's own position lies at weight 1 on one corner: a NaN at the face's other corners stays out.
  const SurfaceLocations own = locate_on_surface(m.V, m.F, m.V.topRows(1));
  const int f = own.face[0];
  Eigen::MatrixXd field = Eigen::MatrixXd::Zero(m.num_vertices(), 1);
  for (int k = 0; k < 3; ++k)
    if (m.F(f, k) != 0) field(m.F(f, k), 0) = std::numeric_limits<double>::quiet_NaN();
  field(0, 0) = 7;
  EXPECT_EQ(interpolate_on_surface(m.F, own, field)(0, 0), 7);
  // ...but a NaN of positive weight makes the value NaN.
  field(0, 0) = std::numeric_limits<double>::quiet_NaN();
  EXPECT_TRUE(std::isnan(interpolate_on_surface(m.F, own, field)(0, 0)));
}

TEST(LocateOnSurface, ZeroAreaFacesAreSkippedAndBadInputsRefused) {
  // Two triangles of a unit square plus a zero-area face along the diagonal: points still land on the square.
  Mesh m;
  m.V.resize(4, 3);
  m.V << 0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0;
  m.F.resize(3, 3);
  m.F << 0, 1, 2, 0, 2, 2, 0, 2, 3;
  Points P(2, 3);
  P << 0.5, 0.5, 1, 0.25, 0.75, -1;
  const SurfaceLocations at = locate_on_surface(m.V, m.F, P);
  for (Index i = 0; i < 2; ++i) {
    EXPECT_NE(at.face[i], 1);
    EXPECT_NEAR(at.distance[i], 1.0, 1e-15);
  }
  auto message_of = [](auto&& call) -> std::string {
    try {
      call();
    } catch (const Error& e) {
      return e.what();
    }
    return "no error";
  };
  Faces only_degenerate(1, 3);
  only_degenerate << 0, 1, 1;
  EXPECT_NE(message_of([&] { locate_on_surface(m.V, only_degenerate, P); }).find("positive area"),
            std::string::npos);
  Faces out_of_range = m.F;
  out_of_range(2, 1) = 9;
  EXPECT_NE(message_of([&] { locate_on_surface(m.V, out_of_range, P); }).find("face 2 has vertex 9"),
            std::string::npos);
  Points bad = P;
  bad(1, 2) = std::numeric_limits<double>::infinity();
  EXPECT_NE(message_of([&] { locate_on_surface(m.V, m.F, bad); }).find("query point 1"), std::string::npos);
  EXPECT_NE(message_of([&] { interpolate_on_surface(m.F, at, m.V.topRows(2)); }).find("values has 2 rows"),
            std::string::npos);
}

}  // namespace locate_on_surface_test
}  // namespace cshapes
