#include "cshapes/geodesics/geodesic_parts.h"

#include <gtest/gtest.h>

#include "cshapes/data/articulated.h"
#include "cshapes/mesh/rigid_transform.h"

namespace cshapes {
namespace geodesic_parts_test {

Mesh generated(const std::string& class_name, int pose = 0, int vertices = 1500) {
  ArticulatedOptions ao;
  ao.poses = pose + 1;
  ao.seed = 5;
  ao.rest.target_vertices = vertices;
  return generate_articulated(class_name, ao).poses[static_cast<size_t>(pose)];
}

// Vertices of each part, core included.
std::vector<int> part_sizes(const GeodesicPartsResult& r) {
  std::vector<int> sizes(static_cast<size_t>(r.part_count()), 0);
  for (Index v = 0; v < r.part.size(); ++v) {
    EXPECT_GE(r.part[v], 0) << v;  // a generated mesh needs no repair: no vertex is dropped
    if (r.part[v] >= 0) ++sizes[static_cast<size_t>(r.part[v])];
  }
  return sizes;
}

TEST(GeodesicParts, BipedHasHeadTwoHandsTwoFeet) {
  const Mesh biped = generated("biped");
  const GeodesicPartsResult r = geodesic_parts(biped);
  ASSERT_EQ(r.extremities.size(), 5u);
  const std::vector<int> sizes = part_sizes(r);
  for (size_t k = 0; k < sizes.size(); ++k) EXPECT_GT(sizes[k], 10) << "part " << k;
  // Each extremity lies in its own part, and is far from the centre.
  for (size_t e = 0; e < r.extremities.size(); ++e) {
    EXPECT_EQ(r.part[r.extremities[e]], static_cast<int>(e) + 1);
    EXPECT_GE(r.extremity_persistence[e], 0.15);
  }
  EXPECT_DOUBLE_EQ(r.extremity_reach[0], 1.0);  // the first is the farthest, and never dies
  EXPECT_DOUBLE_EQ(r.extremity_persistence[0], 1.0);
  EXPECT_LT(r.refused_persistence, 0.1);  // the bumps left out are far below the limbs
  EXPECT_EQ(r.part[r.centre], 0);
  EXPECT_EQ(r.centre_distance[r.centre], 0.0);
}

TEST(GeodesicParts, QuadrupedHasFourLegsHeadAndTail) {
  // The same count in another pose: the parts follow the geometry, not the pose.
  for (int pose : {0, 1}) {
    const GeodesicPartsResult r = geodesic_parts(generated("quadruped", pose));
    EXPECT_EQ(r.extremities.size(), 6u) << "pose " << pose;
  }
}

TEST(GeodesicParts, LabelsAreInvariantUnderRigidMotionAndScale) {
  const Mesh biped = generated("biped", 1);
  const GeodesicPartsResult r = geodesic_parts(biped);
  for (double scale : {1e-3, 1.0, 250.0}) {
    Mesh moved = biped;
    moved.V = random_rigid_transform(11, 3.0, false).apply(biped.V) * scale;
    const GeodesicPartsResult m = geodesic_parts(moved);
    EXPECT_EQ(m.centre, r.centre) << scale;
    EXPECT_EQ(m.extremities, r.extremities) << scale;
    EXPECT_EQ((m.part.array() != r.part.array()).count(), 0) << scale;
    EXPECT_NEAR(m.centre_distance.maxCoeff(), scale * r.centre_distance.maxCoeff(),
                1e-9 * scale * r.centre_distance.maxCoeff());
  }
}

TEST(GeodesicParts, OptionsBoundTheSearch) {
  const Mesh biped = generated("biped");
  GeodesicPartsOptions o;
  o.max_extremities = 2;
  EXPECT_EQ(geodesic_parts(biped, o).extremities.size(), 2u);
  o = GeodesicPartsOptions();
  o.part_fraction = 1e-9;  // no part reaches past its extremity: everything else is core
  const GeodesicPartsResult tiny = geodesic_parts(biped, o);
  EXPECT_EQ(static_cast<size_t>((tiny.part.array() > 0).count()), tiny.extremities.size());
  o = GeodesicPartsOptions();
  o.centre_sources = 0;
  EXPECT_THROW(geodesic_parts(biped, o), Error);
  Mesh cloud;
  cloud.V = biped.V;
  EXPECT_THROW(geodesic_parts(cloud), Error);
}

}  // namespace geodesic_parts_test
}  // namespace cshapes
