// A dataset's distance matrix (pipeline/dataset_distances.h): what it refuses before any work, and a cache
// that cannot be written stopping the run instead of skipping shapes.
#include "cshapes/pipeline/dataset_distances.h"

#include <gtest/gtest.h>

#include <cerrno>
#include <cstring>
#include <filesystem>
#include <string>

#include "cshapes/support/atomic_file.h"
#include "cshapes/support/error.h"
#include "cshapes/mesh/io.h"
#include "cshapes/data/synthetic.h"
#include "tests/test_support.h"

namespace cshapes {
namespace dataset_distances_test {

namespace fs = std::filesystem;

// Four small shapes in two classes, and options that canonize them in a blink (classical MDS on graph
// geodesics).
std::string tiny_dataset(const std::string& tag) {
  const std::string dir = test::scratch_dir(tag);
  write_mesh(dir + "/data/sphere0.off", icosphere(2, 1.0));
  write_mesh(dir + "/data/sphere1.off", icosphere(2, 1.2));
  write_mesh(dir + "/data/torus0.off", torus(12, 6, 1.0, 0.3));
  write_mesh(dir + "/data/torus1.off", torus(12, 6, 1.1, 0.35));
  return dir;
}

DatasetDistanceOptions fast_options(const std::string& dir) {
  DatasetDistanceOptions o;
  o.data = dir + "/data";
  o.canon.method = "cmds";
  o.canon.geodesics.method = GeodesicMethod::Graph;
  o.cache_dir = dir + "/cache";
  o.pairs.icp.pyramid = {50, 150};
  return o;
}

// The matrix itself: every pair's distance is the ICP shape distance of the two canonical forms computed
// alone (brute force, no cache), the matrix is symmetric with a zero diagonal, and a second run serves
// every form and pair from the cache with the same numbers.
TEST(DatasetDistances, EveryEntryIsThePairsOwnShapeDistance) {
  const std::string dir = tiny_dataset("dataset-distances-known");
  const DatasetDistanceOptions o = fast_options(dir);
  const DatasetDistances d = dataset_distances(o);
  ASSERT_EQ(d.names.size(), 4u);
  EXPECT_EQ(d.classes, (std::vector<std::string>{"sphere", "sphere", "torus", "torus"}));
  EXPECT_EQ(d.forms_computed, 4);
  const Eigen::MatrixXd& H = d.distances.hausdorff;
  ASSERT_EQ(H.rows(), 4);
  std::vector<Points> forms;
  for (const std::string& name : d.names) {
    CanonicalFormOptions co = o.canon;
    co.name = name;
    forms.push_back(canonical_form(read_mesh(dir + "/data/" + name + ".off"), co).X);
  }
  PairwiseDistanceOptions po = o.pairs;
  const PairwiseDistanceResult alone = pairwise_distances(forms, {}, po);
  const double scale = H.maxCoeff();
  ASSERT_GT(scale, 0);
  for (Index i = 0; i < 4; ++i) {
    EXPECT_EQ(H(i, i), 0);
    for (Index j = 0; j < 4; ++j) {
      EXPECT_EQ(H(i, j), H(j, i));
      EXPECT_NEAR(H(i, j), alone.hausdorff(i, j), 1e-12 * scale) << i << ", " << j;
    }
  }
  const DatasetDistances again = dataset_distances(o);
  EXPECT_EQ(again.forms_computed, 0);
  EXPECT_EQ(again.forms_cached, 4);
  EXPECT_TRUE(again.distances.hausdorff == H);
}

TEST(DatasetDistances, AFullCacheStopsTheRunInsteadOfSkippingShapes) {
  // Issue 22: with the cache on a full disk, 28 of 30 shapes were "skipped" and a 2×2 matrix came out.
  const std::string dir = tiny_dataset("dataset-distances-full");
  std::vector<std::string> notes;
  DatasetDistanceOptions o = fast_options(dir);
  o.note = [&](const std::string& line) { notes.push_back(line); };
  fail_file_writes_for_testing(2);  // the first form is cached, then the disk is full
  try {
    dataset_distances(o);
    ADD_FAILURE() << "no error";
  } catch (const WriteError& e) {
    const std::string message = e.what();
    EXPECT_NE(message.find(dir + "/cache/forms/"), std::string::npos) << message;
    EXPECT_NE(message.find(std::strerror(ENOSPC)), std::string::npos) << message;
  }
  fail_file_writes_for_testing(0);
  for (const std::string& line : notes) EXPECT_EQ(line.find("skipped"), std::string::npos) << line;
  // The next run, with room on the disk, has the first form and goes on.
  const DatasetDistances again = dataset_distances(fast_options(dir));
  EXPECT_EQ(again.forms_cached, 1);
  EXPECT_EQ(again.forms_computed, 3);
  EXPECT_TRUE(again.skipped.empty());
  fs::remove_all(dir);
}

TEST(DatasetDistances, ACacheFolderThatIsAFileIsRefusedBeforeAnyWork) {
  // Issue 22: "0 usable shapes (30 skipped)" after seconds of work.
  const std::string dir = tiny_dataset("dataset-distances-file");
  DatasetDistanceOptions o = fast_options(dir);
  test::write_text(o.cache_dir, "not a folder");
  std::vector<std::string> notes;
  o.note = [&](const std::string& line) { notes.push_back(line); };
  try {
    dataset_distances(o);
    ADD_FAILURE() << "no error";
  } catch (const WriteError& e) {
    EXPECT_NE(std::string(e.what()).find(o.cache_dir), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("not a folder"), std::string::npos) << e.what();
  }
  EXPECT_TRUE(notes.empty());  // no shape was read or canonized
  fs::remove_all(dir);
}

}  // namespace dataset_distances_test
}  // namespace cshapes
