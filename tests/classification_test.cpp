// Princeton .cla classification files (data/classification.h) and collections listed by them
// (data/dataset.h), and the evaluation tools' matrix forms (eval/distance_csv.h).
#include "cshapes/data/classification.h"

#include <gtest/gtest.h>

#include <cstring>
#include <filesystem>
#include <string>

#include "cshapes/support/atomic_file.h"
#include "cshapes/data/dataset.h"
#include "cshapes/support/error.h"
#include "cshapes/mesh/io.h"
#include "cshapes/data/synthetic.h"
#include "cshapes/eval/distance_csv.h"
#include "cshapes/pipeline/dataset_distances.h"
#include "tests/test_support.h"

namespace cshapes {
namespace classification_test {

namespace fs = std::filesystem;

// The example of the format's documentation: a hierarchy (animal > quadruped > dog, horse), an inner class
// without models, blank lines between classes.
const char* const kExample =
    "PSB 1\n5 17\n\naircraft 0 4\n1119\n1121\n1123\n1125\n\nanimal 0 0\n\nquadruped animal 0\n\n"
    "dog quadruped 7\n86\n87\n88\n89\n90\n91\n92\n\nhorse quadruped 6\n103\n104\n105\n106\n107\n108\n";

TEST(Classification, ReadsTheFormatsOwnExample) {
  const Classification c = parse_classification(kExample, "example.cla");
  ASSERT_EQ(c.classes.size(), 5u);
  EXPECT_EQ(c.classes[0].name, "aircraft");
  EXPECT_EQ(c.classes[0].models, (std::vector<std::string>{"1119", "1121", "1123", "1125"}));
  EXPECT_EQ(c.classes[2].parent, "animal");
  EXPECT_TRUE(c.classes[2].models.empty());
  EXPECT_EQ(c.classes[3].parent, "quadruped");
  EXPECT_EQ(c.classes[4].models.back(), "108");
  EXPECT_EQ(c.classes[4].model_lines.back(), 29);  // line of "108"
  EXPECT_EQ(c.models().size(), 17u);
}

TEST(Classification, WriteThenReadGivesTheSameClassesAndText) {
  const std::string dir = test::scratch_dir("cla-round-trip");
  const Classification c = parse_classification(kExample, "example.cla");
  write_classification(dir + "/a.cla", c);
  const Classification back = read_classification(dir + "/a.cla");
  ASSERT_EQ(back.classes.size(), c.classes.size());
  for (size_t k = 0; k < c.classes.size(); ++k) {
    EXPECT_EQ(back.classes[k].name, c.classes[k].name);
    EXPECT_EQ(back.classes[k].parent, c.classes[k].parent);
    EXPECT_EQ(back.classes[k].models, c.classes[k].models);
  }
  EXPECT_EQ(read_text_file(dir + "/a.cla"), kExample);  // the writer's layout is the documentation's
  // From labels: one class per name, order of first appearance, models in input order.
  const Classification l = classification_from_labels({"a0", "b0", "a1", "c0", "b1"}, {"a", "b", "a", "c", "b"});
  ASSERT_EQ(l.classes.size(), 3u);
  EXPECT_EQ(l.classes[0].models, (std::vector<std::string>{"a0", "a1"}));
  EXPECT_EQ(l.classes[2].name, "c");
  write_classification(dir + "/l.cla", l);
  EXPECT_EQ(read_text_file(dir + "/l.cla"), "PSB 1\n3 5\n\na 0 2\na0\na1\n\nb 0 2\nb0\nb1\n\nc 0 1\nc0\n");
}

// Each bad file is refused with the file, the line and what was wrong.
TEST(Classification, BadFilesAreRefusedNamingTheLine) {
  struct Case {
    const char* text;
    const char* expected;
  };
  const Case cases[] = {
      {"", "the header 'PSB 1'"},
      {"PSB 2\n1 1\nx 0 1\n1\n", "bad.cla:1: format version '2'"},
      {"OFF\n", "bad.cla:1: not a classification file"},
      {"PSB 1\n1 x\n", "bad.cla:2: expected the number of models"},
      {"PSB 1\n1 3\n\ncat 0 3\n1\n2\n", "bad.cla:4: class 'cat' says 3 models, the file ends after 2"},
      {"PSB 1\n1 2\n\ncat 0 2\n1\n2\n3\n", "bad.cla:7: '3' after the last of the 1 classes"},
      {"PSB 1\n1 3\n\ncat 0 2\n1\n2\n", "bad.cla:2: the header announces 3 models, the classes list 2"},
      {"PSB 1\n2 2\n\ncat 0 1\n1\n\ncat 0 1\n2\n", "bad.cla:7: class 'cat' appears twice"},
      {"PSB 1\n1 1\n\ncat dog 1\n1\n", "bad.cla:4: class 'cat' has parent 'dog', which is not defined"},
      {"PSB 1\n2 2\n\ncat 0 1\n1\n\ndog 0 1\n1\n", "bad.cla:8: model '1' is listed twice (first on line 5)"},
      {"PSB 1\n1 1\n\ncat 0 -1\n", "bad.cla:4: expected the model count of its class"},
  };
  for (const Case& c : cases) {
    try {
      parse_classification(c.text, "bad.cla");
      ADD_FAILURE() << "accepted: " << c.text;
    } catch (const Error& e) {
      EXPECT_NE(std::string(e.what()).find(c.expected), std::string::npos) << e.what();
    }
  }
  const std::string dir = test::scratch_dir("cla-bad-write");
  EXPECT_THROW(write_classification(dir + "/x.cla", classification_from_labels({"a b"}, {"c"})), Error);
  EXPECT_THROW(write_classification(dir + "/x.cla", {{{"c", "0", {"1"}, {}}, {"d", "0", {"1"}, {}}}}), Error);
  EXPECT_FALSE(fs::exists(dir + "/x.cla"));
}

// A .cla dataset: ids to files by the stated rule (ID.ext, then mID.ext), classes and order as the file
// says; a model without a file is refused naming the .cla line.
TEST(Classification, DatasetFromAClaFileMapsIdsToFiles) {
  const std::string dir = test::scratch_dir("cla-dataset");
  write_mesh(dir + "/12.off", icosphere(1, 1.0));
  write_mesh(dir + "/m7.ply", icosphere(1, 1.1));
  write_mesh(dir + "/3.obj", torus(8, 4, 1.0, 0.3));
  test::write_text(dir + "/c.cla", "PSB 1\n2 3\n\nround 0 2\n12\n7\n\nring 0 1\n3\n");
  const Dataset d = read_dataset(dir + "/c.cla");
  ASSERT_EQ(d.entries.size(), 3u);
  EXPECT_EQ(d.entries[0].path, dir + "/12.off");
  EXPECT_EQ(d.entries[1].path, dir + "/m7.ply");
  EXPECT_EQ(d.entries[1].name, "m7");
  EXPECT_EQ(d.entries[1].pose, 1);
  EXPECT_EQ(d.entries[2].class_name, "ring");
  EXPECT_EQ(d.classes, (std::vector<std::string>{"round", "ring"}));
  test::write_text(dir + "/missing.cla", "PSB 1\n1 2\n\nround 0 2\n12\n99\n");
  try {
    read_dataset(dir + "/missing.cla");
    ADD_FAILURE() << "a missing model file was accepted";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("missing.cla:6: model '99' of class 'round': no file 99.off"),
              std::string::npos)
        << e.what();
  }
}

// The same collection listed by a folder and by a .cla file (written from the folder's dataset) gives the
// same shapes in the same order and the same distance matrix, entry for entry.
TEST(Classification, ClaAndFolderGiveTheSameMatrix) {
  const std::string dir = test::scratch_dir("cla-vs-folder");
  const std::string manifest = test::generated_dataset(dir + "/gen", 2, 3, 400);
  // The generated folder's meshes without its manifest: a plain folder.
  fs::create_directories(dir + "/data");
  for (const DatasetEntry& e : read_dataset(manifest).entries)
    fs::copy_file(e.path, dir + "/data/" + fs::path(e.path).filename().string());
  const Dataset folder = read_dataset(dir + "/data");
  std::vector<std::string> ids, classes;
  for (const DatasetEntry& e : folder.entries) {
    ids.push_back(e.name);
    classes.push_back(e.class_name);
  }
  write_classification(dir + "/data/collection.cla", classification_from_labels(ids, classes));
  const Dataset listed = read_dataset(dir + "/data/collection.cla");
  ASSERT_EQ(listed.entries.size(), folder.entries.size());
  for (size_t k = 0; k < listed.entries.size(); ++k) EXPECT_EQ(listed.entries[k].path, folder.entries[k].path);

  DatasetDistanceOptions o;
  o.canon.method = "cmds";
  o.canon.geodesics.method = GeodesicMethod::Graph;
  o.pairs.icp.pyramid = {50, 150};
  o.data = dir + "/data";
  const DatasetDistances a = dataset_distances(o);
  o.data = dir + "/data/collection.cla";
  const DatasetDistances b = dataset_distances(o);
  EXPECT_EQ(a.names, b.names);
  EXPECT_EQ(a.classes, b.classes);
  ASSERT_EQ(a.distances.hausdorff.rows(), 6);
  EXPECT_EQ(a.distances.hausdorff, b.distances.hausdorff);
  EXPECT_GT(a.distances.hausdorff.maxCoeff(), 0);
}

// The evaluation tools' forms: text that reads back as the matrix (as %.9g), and the PSB's float32 bytes.
TEST(Classification, MatrixFormsOfTheEvaluationTools) {
  const std::string dir = test::scratch_dir("tool-matrices");
  Eigen::MatrixXd D(3, 3);
  D << 0, 1.5, 2.25, 1.5, 0, 1e-3, 2.25, 1e-3, 0;
  write_dissimilarity_text(dir + "/d.txt", D);
  EXPECT_EQ(read_text_file(dir + "/d.txt"), "0 1.5 2.25\n1.5 0 0.001\n2.25 0.001 0\n");
  const NamedDistances back = read_distance_csv(dir + "/d.txt");
  EXPECT_EQ(back.D, D);
  write_psb_matrix(dir + "/d.matrix", D);
  const std::string bytes = read_file(dir + "/d.matrix");
  ASSERT_EQ(bytes.size(), 9u * 4u);
  for (int k = 0; k < 9; ++k) {
    const unsigned char* b = reinterpret_cast<const unsigned char*>(bytes.data()) + 4 * k;
    const std::uint32_t bits = b[0] | (b[1] << 8) | (b[2] << 16) | (std::uint32_t(b[3]) << 24);
    float value;
    std::memcpy(&value, &bits, 4);
    EXPECT_EQ(value, static_cast<float>(D(k / 3, k % 3))) << k;
  }
}

}  // namespace classification_test
}  // namespace cshapes
