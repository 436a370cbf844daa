// pipeline/generated_shapes.h: the files `cshapes generate` writes, read back — meshes to their fixed six
// decimals, glued pairs, the manifest as a dataset — and the summaries that describe them.
#include "cshapes/pipeline/generated_shapes.h"

#include <gtest/gtest.h>

#include <filesystem>

#include "cshapes/support/atomic_file.h"
#include "cshapes/data/dataset.h"
#include "cshapes/mesh/io.h"
#include "cshapes/data/synthetic.h"
#include "tests/test_support.h"

namespace cshapes {
namespace generated_shapes_test {

namespace fs = std::filesystem;

// Written with six decimals: read back within half a unit of the sixth.
void expect_same_mesh(const std::string& path, const Mesh& expected) {
  const Mesh read = read_mesh(path);
  ASSERT_EQ(read.V.rows(), expected.V.rows()) << path;
  EXPECT_LE((read.V - expected.V).cwiseAbs().maxCoeff(), 5.0000001e-7) << path;
  EXPECT_TRUE(read.F == expected.F) << path;
}

TEST(GeneratedShapes, ArticulatedClassRestAndPosesWithTheirSummary) {
  const std::string dir = test::scratch_dir("generated-class");
  ArticulatedClass c;
  c.skeleton.class_name = "spider";
  c.rest = torus(12, 6);
  c.poses = {torus(12, 6, 1.1, 0.3), torus(12, 6, 1.2, 0.25)};
  c.isometry = {{0.01, 0.1}, {0.02, 0.2}};
  c.redraws = 4;
  const nlohmann::json j = write_articulated_class(c, dir);
  expect_same_mesh(dir + "/spider_rest.off", c.rest);
  expect_same_mesh(dir + "/spider0.off", c.poses[0]);
  expect_same_mesh(dir + "/spider1.off", c.poses[1]);
  EXPECT_EQ(j["class"], "spider");
  EXPECT_EQ(j["vertices"], 72);
  EXPECT_EQ(j["faces"], 144);
  EXPECT_EQ(j["redraws"], 4);
  ASSERT_EQ(j["poses"].size(), 2u);
  EXPECT_EQ(j["poses"][1]["file"], (fs::path(dir) / "spider1.off").string());
  EXPECT_EQ(j["poses"][1]["edge_change_mean"], 0.02);
  EXPECT_EQ(j["poses"][1]["edge_change_max"], 0.2);
}

TEST(GeneratedShapes, GluedHandFilesAndPairs) {
  const std::string dir = test::scratch_dir("generated-hand");
  GluedHand hand;
  hand.separated = icosphere(1);
  hand.glued = icosphere(2);
  hand.glued_pairs = {{3, 17}, {5, 40}};
  write_glued_hand(hand, dir);
  expect_same_mesh(dir + "/hand_separated.off", hand.separated);
  expect_same_mesh(dir + "/hand_glued.off", hand.glued);
  EXPECT_EQ(
      read_file(dir + "/hand_glued_pairs.json"),
      "{\n  \"pairs\": [\n    [\n      3,\n      17\n    ],\n    [\n      5,\n      40\n    ]\n  ]\n}\n");
}

TEST(GeneratedShapes, DatasetReadsBackThroughItsManifest) {
  const std::string dir = test::scratch_dir("generated-dataset");
  std::vector<ArticulatedShape> shapes(3);
  const char* names[] = {"biped0", "biped1", "biped2"};
  for (int i = 0; i < 3; ++i) {
    shapes[i].name = names[i];
    shapes[i].class_name = "biped";
    shapes[i].pose = i;
    shapes[i].mesh = torus(10 + i, 5);
    shapes[i].isometry = {0.01 * i, 0.1 * i};
  }
  shapes[2].noisy = true;
  shapes[2].glued_pairs = {{1, 2}};
  const nlohmann::json summary = write_articulated_dataset(shapes, dir);
  const Dataset dataset = read_dataset(dir + "/manifest.csv");
  ASSERT_EQ(dataset.entries.size(), 3u);
  for (int i = 0; i < 3; ++i) {
    EXPECT_EQ(dataset.entries[i].name, names[i]);
    EXPECT_EQ(dataset.entries[i].class_name, "biped");
    EXPECT_EQ(dataset.entries[i].pose, i);
    EXPECT_EQ(dataset.entries[i].noisy, i == 2);
    expect_same_mesh(dataset.entries[i].path, shapes[i].mesh);
    EXPECT_EQ(summary[i]["file"], std::string(names[i]) + ".off");
    EXPECT_EQ(summary[i]["vertices"], (10 + i) * 5);
    EXPECT_EQ(summary[i]["genus"], 1);
    EXPECT_EQ(summary[i]["noisy"], i == 2);
  }
  EXPECT_FALSE(fs::exists(dir + "/biped1_glued_pairs.json"));
  EXPECT_EQ(nlohmann::json::parse(read_file(dir + "/biped2_glued_pairs.json"))["pairs"],
            nlohmann::json::parse("[[1, 2]]"));
}

}  // namespace generated_shapes_test
}  // namespace cshapes
