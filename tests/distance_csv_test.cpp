#include "cshapes/eval/distance_csv.h"

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>

#include "cshapes/support/atomic_file.h"
#include "cshapes/support/error.h"
#include "tests/test_support.h"

namespace cshapes {
namespace distance_csv_test {

TEST(DistanceCsv, RoundTrip) {
  std::string dir = test::scratch_dir("csv");
  Eigen::MatrixXd D(3, 3);
  D << 0, 1.25, 1e-7, 1.25, 0, 3, 1e-7, 3, 0;
  write_distance_csv(dir + "/d.csv", {"cat0", "cat1", "dog0"}, D);
  NamedDistances r = read_distance_csv(dir + "/d.csv");
  EXPECT_EQ(r.names, (std::vector<std::string>{"cat0", "cat1", "dog0"}));
  EXPECT_LT((r.D - D).cwiseAbs().maxCoeff(), 1e-9 * 3);
  EXPECT_THROW(write_distance_csv(dir + "/bad.csv", {"a,b", "c", "d"}, D), Error);
  std::filesystem::remove_all(dir);
}

TEST(DistanceCsv, ReadsNameColumnPlainAndSpaces) {
  std::string dir = test::scratch_dir("csv-formats");
  test::write_text(dir + "/names.csv", "name,a,b\na,0,2\nb,2,0\n");
  NamedDistances n = read_distance_csv(dir + "/names.csv");
  EXPECT_EQ(n.names, (std::vector<std::string>{"a", "b"}));
  EXPECT_EQ(n.D(0, 1), 2.0);
  test::write_text(dir + "/rows.csv", "a,0,2\nb,2,0\n");  // names in the first column only
  EXPECT_EQ(read_distance_csv(dir + "/rows.csv").names, (std::vector<std::string>{"a", "b"}));
  test::write_text(dir + "/plain.txt", "# comment\n0 1 inf\n1 0 2\n\ninf 2 0\n");
  NamedDistances p = read_distance_csv(dir + "/plain.txt");
  EXPECT_EQ(p.names, (std::vector<std::string>{"0", "1", "2"}));
  EXPECT_TRUE(std::isinf(p.D(0, 2)));
  test::write_text(dir + "/ragged.csv", "a,b\n0,1\n1\n");
  EXPECT_THROW(read_distance_csv(dir + "/ragged.csv"), Error);
  test::write_text(dir + "/word.csv", "a,b\n0,x\n1,0\n");
  EXPECT_THROW(read_distance_csv(dir + "/word.csv"), Error);
  test::write_text(dir + "/notsquare.csv", "a,b,c\n0,1,2\n1,0,2\n");
  EXPECT_THROW(read_distance_csv(dir + "/notsquare.csv"), Error);
  std::filesystem::remove_all(dir);
}

TEST(DistanceCsv, ClassOfShapeName) {
  // The datasets' rule (trailing digits dropped), after the directory and extension.
  EXPECT_EQ(class_of_shape_name("cat0"), "cat");
  EXPECT_EQ(class_of_shape_name("victoria10"), "victoria");
  EXPECT_EQ(class_of_shape_name("/data/tosca5k/michael5.off"), "michael");
  EXPECT_EQ(class_of_shape_name("plane.ply"), "plane");
  EXPECT_EQ(class_of_shape_name("007"), "007");
}

TEST(DistanceCsv, LabelsFile) {
  std::string dir = test::scratch_dir("labels");
  std::vector<std::string> names = {"cat0", "dog1", "x"};
  test::write_text(dir + "/named.csv", "name,class\ndog1.off,quadruped\ncat0,quadruped\nx,other\n");
  EXPECT_EQ(read_labels_csv(dir + "/named.csv", names),
            (std::vector<std::string>{"quadruped", "quadruped", "other"}));
  test::write_text(dir + "/ordered.csv", "a\nb\na\n");
  EXPECT_EQ(read_labels_csv(dir + "/ordered.csv", names), (std::vector<std::string>{"a", "b", "a"}));
  test::write_text(dir + "/missing.csv", "cat0,a\ndog1,b\n");
  EXPECT_THROW(read_labels_csv(dir + "/missing.csv", names), Error);
  test::write_text(dir + "/short.csv", "a\nb\n");
  EXPECT_THROW(read_labels_csv(dir + "/short.csv", names), Error);
  std::filesystem::remove_all(dir);
}

// What a matrix is (issue 60): written above the classes as comment lines, which the labels reader skips,
// read back by field; a file without them describes nothing.
TEST(DistanceCsv, TheLabelsFileDescribesTheMatrix) {
  std::string dir = test::scratch_dir("labels-description");
  const std::vector<std::string> names = {"cat0", "dog1"}, classes = {"cat", "dog"};
  write_labels_csv(dir + "/D.labels.csv", names, classes, {"Coulomb", "Hausdorff", "tosca5k"});
  EXPECT_EQ(read_labels_csv(dir + "/D.labels.csv", names), classes);
  const MatrixDescription d = read_matrix_description(dir + "/D.labels.csv");
  EXPECT_EQ(d.method, "Coulomb");
  EXPECT_EQ(d.distance, "Hausdorff");
  EXPECT_EQ(d.data, "tosca5k");
  EXPECT_EQ(matrix_description_text(d), "Coulomb, Hausdorff distance, tosca5k");
  EXPECT_EQ(matrix_description_text({"", "Chamfer", ""}), "Chamfer distance");
  write_labels_csv(dir + "/plain.csv", names, classes);
  EXPECT_EQ(read_file(dir + "/plain.csv"), "name,class\ncat0,cat\ndog1,dog\n");
  EXPECT_EQ(matrix_description_text(read_matrix_description(dir + "/plain.csv")), "");
  EXPECT_THROW(write_labels_csv(dir + "/bad.csv", names, classes, {"two\nlines", "", ""}), Error);
  std::filesystem::remove_all(dir);
}

TEST(DistanceCsv, ConflictingLabelsAreRefusedNamingBothLines) {
  // Issue 22: `evaluate` accepted a shape given two classes.
  const std::string dir = test::scratch_dir("labels-conflict");
  test::write_text(dir + "/conflict.csv", "name,class\ncat0,cat\ndog1,dog\ncat0,dog\n");
  const std::string message = test::error_of([&] { read_labels_csv(dir + "/conflict.csv", {"cat0", "dog1"}); });
  EXPECT_NE(message.find("conflict.csv:4"), std::string::npos) << message;
  EXPECT_NE(message.find("'cat0'"), std::string::npos) << message;
  EXPECT_NE(message.find("line 2"), std::string::npos) << message;
  // The same class twice is no conflict.
  test::write_text(dir + "/repeated.csv", "cat0,cat\ndog1,dog\ncat0,cat\n");
  EXPECT_EQ(read_labels_csv(dir + "/repeated.csv", {"cat0", "dog1"}),
            (std::vector<std::string>{"cat", "dog"}));
  std::filesystem::remove_all(dir);
}

// Issue 36: a NUL byte inside a number ("5\0448") was read as 5, and a labels file of empty classes put
// every shape in class '' (mAP 1.0). Both are refused naming the file and line.
TEST(DistanceCsv, ANulByteInANumberAndEmptyClassesAreRefused) {
  const std::string dir = test::scratch_dir("nul-and-empty");
  test::write_text(dir + "/nul.csv", std::string("a0,a1\n0,5") + '\0' + "448\n5,0\n");
  const std::string nul = test::error_of([&] { read_distance_csv(dir + "/nul.csv"); });
  EXPECT_NE(nul.find("nul.csv"), std::string::npos) << nul;
  test::write_text(dir + "/ok.csv", "a0,a1\n0,5448\n5448,0\n");
  EXPECT_EQ(read_distance_csv(dir + "/ok.csv").D(0, 1), 5448);
  test::write_text(dir + "/empty_named.csv", "cat0,\ndog1,\n");
  const std::string named = test::error_of([&] { read_labels_csv(dir + "/empty_named.csv", {"cat0", "dog1"}); });
  EXPECT_NE(named.find("empty_named.csv:1: empty class name"), std::string::npos) << named;
  test::write_text(dir + "/empty_name.csv", ",cat\ndog1,dog\n");
  const std::string name = test::error_of([&] { read_labels_csv(dir + "/empty_name.csv", {"cat0", "dog1"}); });
  EXPECT_NE(name.find("empty_name.csv:1: empty shape name"), std::string::npos) << name;
  std::filesystem::remove_all(dir);
}

TEST(DistanceCsv, MatrixChecksRefuseOrWarnByRule) {
  // Issue 22: `evaluate` accepted asymmetric, negative and non-zero-diagonal matrices and duplicate names.
  NamedDistances m;
  m.names = {"a0", "a1", "b0"};
  m.D.resize(3, 3);
  m.D << 0, 1, 2, 1, 0, 3, 2, 3, 0;
  EXPECT_TRUE(check_distance_matrix(m, "m.csv").empty());

  NamedDistances negative = m;
  negative.D(0, 2) = -0.5;
  std::string message = test::error_of([&] { check_distance_matrix(negative, "m.csv"); });
  EXPECT_NE(message.find("m.csv"), std::string::npos) << message;
  EXPECT_NE(message.find("'a0' to 'b0'"), std::string::npos) << message;
  EXPECT_NE(message.find(">= 0"), std::string::npos) << message;

  NamedDistances twice = m;
  twice.names[2] = "a0";
  message = test::error_of([&] { check_distance_matrix(twice, "m.csv"); });
  EXPECT_NE(message.find("'a0' appears twice"), std::string::npos) << message;

  NamedDistances asymmetric = m;
  asymmetric.D(1, 2) = 3.5;
  std::vector<std::string> warnings = check_distance_matrix(asymmetric, "m.csv");
  ASSERT_EQ(warnings.size(), 1u);
  EXPECT_NE(warnings[0].find("not symmetric"), std::string::npos) << warnings[0];
  EXPECT_NE(warnings[0].find("'a1' and 'b0'"), std::string::npos) << warnings[0];

  NamedDistances diagonal = m;
  diagonal.D(2, 2) = 0.25;
  warnings = check_distance_matrix(diagonal, "m.csv");
  ASSERT_EQ(warnings.size(), 1u);
  EXPECT_NE(warnings[0].find("diagonal"), std::string::npos) << warnings[0];
  EXPECT_NE(warnings[0].find("'b0'"), std::string::npos) << warnings[0];

  // Rounding far below the largest entry is no asymmetry.
  NamedDistances rounded = m;
  rounded.D(0, 1) = 1 + 1e-14;
  EXPECT_TRUE(check_distance_matrix(rounded, "m.csv").empty());
}

}  // namespace distance_csv_test
}  // namespace cshapes
