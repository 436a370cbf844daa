#include "core/synthetic.h"

#include <gtest/gtest.h>

#include <cmath>
#include <map>

#include "core/error.h"

namespace cshapes {
namespace {

constexpr double kPi = 3.14159265358979323846;

// Signed volume (positive when faces are counter-clockwise seen from outside) and area.
double signed_volume(const Mesh& m) {
  double v = 0;
  for (Index f = 0; f < m.num_faces(); ++f)
    v += m.V.row(m.F(f, 0)).dot(m.V.row(m.F(f, 1)).cross(m.V.row(m.F(f, 2)))) / 6;
  return v;
}
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

}  // namespace
}  // namespace cshapes
