// Input vertices carried to a remesh (pipeline/remesh_samples.h): the distances they moved on a real remesh,
// and the other part of a contact on a known answer: two parallel sheets closer together than one sheet's
// "remesh" lies off its surface.
#include "cshapes/pipeline/remesh_samples.h"

#include <gtest/gtest.h>

#include <numeric>

#include "cshapes/support/error.h"
#include "cshapes/mesh/remesh.h"
#include "cshapes/data/synthetic.h"

namespace cshapes {
namespace remesh_samples_test {

// Two meshes in one: b's vertices and faces after a's.
Mesh joined(const Mesh& a, const Mesh& b) {
  Mesh m;
  m.V.resize(a.V.rows() + b.V.rows(), 3);
  m.V << a.V, b.V;
  m.F.resize(a.F.rows() + b.F.rows(), 3);
  m.F << a.F, (b.F.array() + static_cast<int>(a.V.rows())).matrix();
  return m;
}

Mesh lifted(Mesh m, double dz) {
  m.V.col(2).array() += dz;
  return m;
}

TEST(RemeshSamples, VerticesOfARemeshedTorusMoveLessThanTheHausdorffDistanceAndStayOnTheirPart) {
  const Mesh input = torus(60, 24, 1.0, 0.35);
  RemeshOptions o;
  o.target_vertices = 500;
  const Mesh coarse = remesh(input, o).mesh;
  std::vector<int> all(static_cast<size_t>(input.num_vertices()));
  std::iota(all.begin(), all.end(), 0);
  const RemeshSamples s = carry_to_remesh(input, coarse, all);
  ASSERT_EQ(s.at.face.size(), input.num_vertices());
  EXPECT_EQ(s.vertices, all);
  const double diagonal = bbox_diagonal(input.V);
  // Each vertex's closest point is what the sampled Hausdorff distance measures at it: no farther.
  EXPECT_GT(s.max_distance, 0.0);
  EXPECT_LE(s.max_distance, hausdorff_distance(input, coarse) / diagonal * (1 + 1e-9));
  EXPECT_LE(s.mean_distance, s.max_distance);
  EXPECT_NEAR(s.max_distance, s.at.distance.maxCoeff() / diagonal, 1e-15);
  EXPECT_EQ(s.relocated, 0);
  EXPECT_EQ(s.off_part, 0);
}

TEST(RemeshSamples, ASheetCloserToTheOtherSheetThanToItsOwnRemeshIsLocatedOnItsOwn) {
  // Input: two parallel unit squares 0.01 apart (two parts, as an arm on a body). "Remesh": the same squares,
  // coarser, the lower one 0.02 below its surface: every vertex of the lower square is nearer the upper
  // remesh, whose triangles lie on the other part, and is located on its own square's remesh instead, right
  // below it; the upper square's vertices are on their own.
  const double gap = 0.01;
  const Mesh input = joined(grid(21, 21), lifted(grid(21, 21), gap));
  const Mesh lower_remesh = lifted(grid(6, 6), -2 * gap), upper_remesh = lifted(grid(6, 6), gap);
  const Mesh remeshed = joined(lower_remesh, upper_remesh);
  std::vector<int> lower, upper;
  for (int v = 0; v < 441; v += 7) lower.push_back(v), upper.push_back(441 + v);
  const RemeshSamples moved = carry_to_remesh(input, remeshed, lower);
  EXPECT_EQ(moved.relocated, static_cast<int>(lower.size()));
  EXPECT_EQ(moved.off_part, 0);
  for (Index k = 0; k < moved.at.distance.size(); ++k) {
    EXPECT_LT(moved.at.face[k], lower_remesh.num_faces()) << "sample " << k;  // the lower square's faces
    EXPECT_NEAR(moved.at.distance[k], 2 * gap, 1e-12);
    EXPECT_LT((moved.at.closest.row(k) - input.V.row(lower[static_cast<size_t>(k)])).head<2>().norm(), 1e-12);
  }
  const RemeshSamples on = carry_to_remesh(input, remeshed, upper);
  EXPECT_EQ(on.relocated + on.off_part, 0);
  EXPECT_LT(on.max_distance, 1e-12);
  // The lower square with its own remesh in place: on its part. Without one: off it, left where it was.
  const Mesh in_place = joined(grid(6, 6), upper_remesh);
  const RemeshSamples placed = carry_to_remesh(input, in_place, lower);
  EXPECT_EQ(placed.relocated + placed.off_part, 0);
  const RemeshSamples lost = carry_to_remesh(input, upper_remesh, lower);
  EXPECT_EQ(lost.relocated, 0);
  EXPECT_EQ(lost.off_part, static_cast<int>(lower.size()));
  for (Index k = 0; k < lost.at.distance.size(); ++k) EXPECT_NEAR(lost.at.distance[k], gap, 1e-12);
}

TEST(RemeshSamples, AVertexOutOfRangeIsRefused) {
  const Mesh m = icosphere(1);
  try {
    carry_to_remesh(m, m, {0, 42});
    FAIL() << "expected an error";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("vertex 42"), std::string::npos) << e.what();
  }
}

}  // namespace remesh_samples_test
}  // namespace cshapes
