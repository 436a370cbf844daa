#include "cshapes/data/articulated.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <map>

#include "cshapes/support/atomic_file.h"
#include "cshapes/support/output_folder.h"
#include "cshapes/data/dataset.h"
#include "cshapes/geodesics/geodesics.h"
#include "cshapes/mesh/io.h"
#include "cshapes/mesh/marching_tetrahedra.h"
#include "cshapes/mesh/remesh.h"
#include "tests/test_support.h"

namespace cshapes {
namespace articulated_test {

constexpr double kPi = 3.14159265358979323846;

TEST(MarchingTetrahedra, SphereIsClosedAndOnTheSphere) {
  const double r = 3.0, cell = 0.25;
  Mesh m = marching_tetrahedra([&](const Eigen::Vector3d& x) { return x.norm() - r; },
                               Eigen::Vector3d::Constant(-4), Eigen::Vector3d::Constant(4), {cell, 0.05});
  MeshInfo info = mesh_info(m);
  EXPECT_EQ(info.euler_characteristic, 2);
  EXPECT_EQ(info.components, 1);
  EXPECT_EQ(info.boundary_edges, 0);
  EXPECT_EQ(info.nonmanifold_edges, 0);
  // Linear interpolation along grid edges: within a fraction of a cell of the sphere (chord sag ~ cell²/r).
  for (Index i = 0; i < m.num_vertices(); ++i) EXPECT_NEAR(m.V.row(i).norm(), r, cell * 0.2);
  EXPECT_NEAR(info.area, 4 * kPi * r * r, 4 * kPi * r * r * 0.03);
  // Outward orientation: positive signed volume ≈ 4/3 π r³.
  double volume = 0;
  for (Index f = 0; f < m.num_faces(); ++f)
    volume += m.V.row(m.F(f, 0)).dot(m.V.row(m.F(f, 1)).cross(m.V.row(m.F(f, 2)))) / 6;
  EXPECT_NEAR(volume, 4.0 / 3 * kPi * r * r * r, 4.0 / 3 * kPi * r * r * r * 0.03);
}

TEST(MarchingTetrahedra, TorusHasGenusOne) {
  Mesh m = marching_tetrahedra(
      [](const Eigen::Vector3d& x) { return std::hypot(std::hypot(x.x(), x.y()) - 2.0, x.z()) - 0.7; },
      Eigen::Vector3d(-3, -3, -1), Eigen::Vector3d(3, 3, 1), {0.1, 0.05});
  MeshInfo info = mesh_info(m);
  EXPECT_EQ(info.genus, 1);
  EXPECT_EQ(info.components, 1);
}

TEST(Articulated, SkinningWeightsArePartitionsOfUnity) {
  Skeleton s = articulated_skeleton("hand");
  Mesh rest = articulated_rest_mesh(s, {1000, 0.5});
  Eigen::MatrixXd W = skinning_weights(s, rest.V);
  EXPECT_NEAR((W.rowwise().sum().array() - 1).abs().maxCoeff(), 0.0, 1e-12);
  EXPECT_GE(W.minCoeff(), 0.0);
  EXPECT_NEAR(W.col(0).norm(), 0.0, 0.0);  // the root has no bone
  // The neutral pose reproduces the rest mesh; a rigid-only pose (all angles zero) is exact.
  Points same = pose_mesh(s, rest.V, W, neutral_pose(s));
  EXPECT_NEAR((same - rest.V).cwiseAbs().maxCoeff(), 0.0, 1e-9);
}

TEST(Articulated, ClassesArePosedNearIsometricallyAndDifferFromEachOther) {
  // Pose-invariant descriptor: deciles of the geodesic distances from 12 fixed vertices over the largest of
  // them, and sqrt(area) over that largest distance (how much surface per length: many limbs or few).
  // Edge-graph distances (Dijkstra): the descriptor was designed and measured with them; no set-up per source.
  GeodesicOptions graph;
  graph.method = GeodesicMethod::Graph;
  auto descriptor = [&graph](const Mesh& m) {
    std::vector<double> all;
    for (int k = 0; k < 12; ++k) {
      Eigen::VectorXd d = geodesic_distances(m, {static_cast<int>(k * m.num_vertices() / 12)}, graph);
      all.insert(all.end(), d.data(), d.data() + d.size());
    }
    std::sort(all.begin(), all.end());
    const double diameter = all.back();
    Eigen::VectorXd q(10);
    for (int i = 0; i < 9; ++i) q[i] = all[(i + 1) * all.size() / 10] / diameter;
    q[9] = std::sqrt(surface_area(m.V, m.F)) / diameter;
    return q;
  };
  std::map<std::string, std::vector<Eigen::VectorXd>> descriptors;
  ArticulatedOptions o;
  o.poses = 3;
  o.seed = 11;
  for (const std::string& name : articulated_classes()) {
    ArticulatedClass c = generate_articulated(name, o);
    MeshInfo info = mesh_info(c.rest);
    EXPECT_NEAR(static_cast<double>(info.vertices), 3500.0, 35.0) << name;
    EXPECT_EQ(info.euler_characteristic, 2) << name;
    EXPECT_EQ(info.components, 1) << name;
    EXPECT_EQ(info.boundary_edges, 0) << name;
    ASSERT_EQ(c.poses.size(), 3u);
    for (size_t p = 0; p < c.poses.size(); ++p) {
      EXPECT_TRUE(c.poses[p].F == c.rest.F) << name;  // shared connectivity and vertex order
      EXPECT_FALSE(self_intersects(c.poses[p])) << name << p;
      // Near-isometric: bones are rigid, only the joints stretch. Mean relative edge-length change < 5%.
      EXPECT_LT(c.isometry[p].mean, 0.05) << name << " pose " << p;
      std::printf("[ metric   ] %s pose %zu: edge length change mean %.2f%%, max %.1f%%\n", name.c_str(), p,
                  100 * c.isometry[p].mean, 100 * c.isometry[p].max);
      // The pose really moved something (not the rest mesh again).
      EXPECT_GT((c.poses[p].V - c.rest.V).rowwise().norm().maxCoeff(), 0.05 * info.bbox_diagonal) << name;
      descriptors[name].push_back(descriptor(c.poses[p]));
    }
  }
  // Distinct classes differ: every pose's nearest other shape (by descriptor) is a pose of its own class, and
  // on average a class is much tighter than the distances between classes.
  double sum_within = 0, sum_between = 0;
  int n_within = 0, n_between = 0;
  for (const auto& [a, da] : descriptors)
    for (size_t i = 0; i < da.size(); ++i) {
      double nearest_same = 1e300, nearest_other = 1e300;
      for (const auto& [b, db] : descriptors)
        for (size_t j = 0; j < db.size(); ++j) {
          if (a == b && i == j) continue;
          double d = (da[i] - db[j]).lpNorm<1>();
          (a == b ? nearest_same : nearest_other) = std::min(a == b ? nearest_same : nearest_other, d);
          (a == b ? sum_within : sum_between) += d;
          ++(a == b ? n_within : n_between);
        }
      EXPECT_LT(nearest_same, nearest_other) << a << " pose " << i;
    }
  std::printf(
      "[ metric   ] geodesic descriptor distance: mean within a class %.3f, mean between classes %.3f\n",
      sum_within / n_within, sum_between / n_between);
  EXPECT_LT(2 * sum_within / n_within, sum_between / n_between);
}

TEST(Articulated, GluedHandHasOneHandlePerGlueAndTheSameVertices) {
  GluedHand h = generate_glued_hand(0, 3);
  MeshInfo a = mesh_info(h.separated), b = mesh_info(h.glued);
  EXPECT_EQ(a.genus, 0);
  EXPECT_EQ(b.genus, 3);
  EXPECT_EQ(b.components, 1);
  EXPECT_TRUE(h.separated.V == h.glued.V);
  ASSERT_EQ(h.glued_pairs.size(), 3u);
  // Adjacent fingers: every glued pair lies in the finger region (beyond the knuckles, y > 38).
  for (auto [p, q] : h.glued_pairs) {
    EXPECT_GT(h.separated.V(p, 1), 38.0);
    EXPECT_GT(h.separated.V(q, 1), 38.0);
  }
}

std::map<std::string, std::string> folder_bytes(const std::string& dir) {
  std::map<std::string, std::string> out;
  for (const auto& e : std::filesystem::directory_iterator(dir))
    if (e.path().filename() != kOutputRecordName)  // the folder's record (support/output_folder.h)
      out[e.path().filename().string()] = read_file(e.path().string());
  return out;
}

TEST(Articulated, SameSeedGivesByteIdenticalDatasetsWhateverTheThreads) {
  std::string a = test::scratch_dir("gen_a"), b = test::scratch_dir("gen_b"), c = test::scratch_dir("gen_c");
  const std::string args = " -q generate dataset --poses 2 --noisy 1 --vertices 1000 --out ";
  ASSERT_EQ(test::run_cli("--threads 1" + args + a + " --seed 5 --classes 2").exit_code, 0);
  ASSERT_EQ(test::run_cli("--threads 2" + args + b + " --seed 5 --classes 2").exit_code, 0);
  auto fa = folder_bytes(a), fb = folder_bytes(b);
  EXPECT_EQ(fa.size(), 2u * 3 + 2 + 1);  // 6 meshes, 2 pairs files, the manifest
  EXPECT_TRUE(fa == fb);
  ASSERT_EQ(test::run_cli(args + c + " --seed 6 --classes 1").exit_code, 0);
  auto fc = folder_bytes(c);
  EXPECT_NE(fa["biped1.off"], fc["biped1.off"]);
  // The manifest reads back: 2 classes, the noisy pose marked, genus 2 there.
  Dataset d = read_dataset(a);
  EXPECT_EQ(d.classes, (std::vector<std::string>{"biped", "quadruped"}));
  ASSERT_EQ(d.entries.size(), 6u);
  EXPECT_TRUE(d.entries[2].noisy);
  EXPECT_EQ(mesh_info(read_mesh(d.entries[2].path)).genus, 2);
  EXPECT_EQ(mesh_info(read_mesh(d.entries[1].path)).genus, 0);
}

TEST(Articulated, SwissRollCommandHasThePapersSize) {
  std::string dir = test::scratch_dir("swiss");
  ASSERT_EQ(test::run_cli("-q generate swissroll -o " + dir + "/s.off").exit_code, 0);
  EXPECT_EQ(read_mesh(dir + "/s.off").num_vertices(), 561);
  ASSERT_EQ(test::run_cli("-q generate swissroll --vertices 2000 -o " + dir + "/t.off").exit_code, 0);
  EXPECT_NEAR(static_cast<double>(read_mesh(dir + "/t.off").num_vertices()), 2000.0, 20.0);
}

}  // namespace articulated_test
}  // namespace cshapes
