#include "cshapes/eval/retrieval.h"

#include <gtest/gtest.h>

#include <cmath>

#include "cshapes/support/atomic_file.h"
#include "cshapes/support/error.h"
#include "cshapes/eval/distance_csv.h"
#include "cshapes/experiments/figures.h"
#include "tests/test_support.h"

#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>

namespace cshapes {
namespace retrieval_test {

// Seven shapes: 0, 1, 2 of class 0; 3, 4, 5 of class 1; 6 alone in class 2 (too small: not a query, but a
// result of the others). Symmetric distances, all distinct, so every ranking is unambiguous:
//
//        0     1     2     3     4     5     6
//   0    -     1     5     2     6     7     3
//   1    1     -     4     8     9    10    11
//   2    5     4     -    12    13    14    0.5
//   3    2     8    12     -    1.5   16    17
//   4    6     9    13    1.5    -    2.5   18
//   5    7    10    14    16    2.5    -    19
//   6    3    11    0.5   17    18    19     -
Eigen::MatrixXd hand_matrix() {
  Eigen::MatrixXd D(7, 7);
  D << 0, 1, 5, 2, 6, 7, 3,       //
      1, 0, 4, 8, 9, 10, 11,      //
      5, 4, 0, 12, 13, 14, 0.5,   //
      2, 8, 12, 0, 1.5, 16, 17,   //
      6, 9, 13, 1.5, 0, 2.5, 18,  //
      7, 10, 14, 16, 2.5, 0, 19,  //
      3, 11, 0.5, 17, 18, 19, 0;
  return D;
}
const std::vector<int> kLabels = {0, 0, 0, 1, 1, 1, 2};

// By hand. Every query has C = 3, so R = C − 1 = 2 relevant results; N − 1 = 6 results, so the E-measure
// looks at K = min(32, 6) = 6 results, which always hold both relevant ones: e = 2·2/(6 + 2) = 0.5.
// Ideal DCG = 1 + 1/log2(2) = 2.
// clang-format off
//   query  ranking       relevant at  nn  ft   st   dcg                          ap
//   0      1 3 6 2 4 5   1, 4         1   1/2  1    (1 + 1/log2 4)/2 = 0.75      (1/1 + 2/4)/2 = 0.75
//   1      0 2 3 4 5 6   1, 2         1   1    1    (1 + 1)/2 = 1                (1 + 1)/2 = 1
//   2      6 1 0 3 4 5   2, 3         0   1/2  1    (1/log2 2 + 1/log2 3)/2      (1/2 + 2/3)/2 = 7/12
//   3      4 0 1 2 5 6   1, 5         1   1/2  1/2  (1 + 1/log2 5)/2             (1 + 2/5)/2 = 0.7
//   4      3 5 0 1 2 6   1, 2         1   1    1    1                            1
//   5      4 0 1 2 3 6   1, 5         1   1/2  1/2  (1 + 1/log2 5)/2             0.7
//   6      skipped (class of 1)
// clang-format on
double dcg_q2() {
  return (1.0 + 1.0 / std::log2(3.0)) / 2.0;
}
double dcg_q3() {
  return (1.0 + 1.0 / std::log2(5.0)) / 2.0;
}

TEST(Retrieval, EveryMeasureMatchesTheHandComputation) {
  RetrievalResult r = evaluate_retrieval(hand_matrix(), kLabels);
  ASSERT_EQ(r.queries.size(), 6u);
  EXPECT_EQ(r.skipped, 1);
  const std::vector<std::vector<int>> rankings = {{1, 3, 6, 2, 4, 5}, {0, 2, 3, 4, 5, 6}, {6, 1, 0, 3, 4, 5},
                                                  {4, 0, 1, 2, 5, 6}, {3, 5, 0, 1, 2, 6}, {4, 0, 1, 2, 3, 6}};
  const double nn[] = {1, 1, 0, 1, 1, 1};
  const double ft[] = {0.5, 1, 0.5, 0.5, 1, 0.5};
  const double st[] = {1, 1, 1, 0.5, 1, 0.5};
  const double dcg[] = {0.75, 1, dcg_q2(), dcg_q3(), 1, dcg_q3()};
  const double ap[] = {0.75, 1, 7.0 / 12, 0.7, 1, 0.7};
  for (int q = 0; q < 6; ++q) {
    const QueryResult& query = r.queries[static_cast<size_t>(q)];
    EXPECT_EQ(query.query, q);
    EXPECT_EQ(query.ranking, rankings[static_cast<size_t>(q)]) << "query " << q;
    EXPECT_DOUBLE_EQ(query.scores.nn, nn[q]) << "query " << q;
    EXPECT_DOUBLE_EQ(query.scores.ft, ft[q]) << "query " << q;
    EXPECT_DOUBLE_EQ(query.scores.st, st[q]) << "query " << q;
    EXPECT_DOUBLE_EQ(query.scores.e, 0.5) << "query " << q;
    EXPECT_DOUBLE_EQ(query.scores.dcg, dcg[q]) << "query " << q;
    EXPECT_DOUBLE_EQ(query.scores.ap, ap[q]) << "query " << q;
  }
  // Means over the 6 queries.
  EXPECT_DOUBLE_EQ(r.mean.nn, 5.0 / 6);
  EXPECT_DOUBLE_EQ(r.mean.ft, 4.0 / 6);
  EXPECT_DOUBLE_EQ(r.mean.st, 5.0 / 6);
  EXPECT_DOUBLE_EQ(r.mean.e, 0.5);
  EXPECT_DOUBLE_EQ(r.mean.dcg, (0.75 + 1 + dcg_q2() + 2 * dcg_q3() + 1) / 6);
  EXPECT_DOUBLE_EQ(r.mean.ap, (0.75 + 1 + 7.0 / 12 + 0.7 + 1 + 0.7) / 6);  // mAP = 0.78889
  // Per class: class 0 = queries 0-2, class 1 = queries 3-5, class 2 none.
  EXPECT_EQ(r.class_queries, (std::vector<int>{3, 3, 0}));
  EXPECT_DOUBLE_EQ(r.class_mean[0].nn, 2.0 / 3);
  EXPECT_DOUBLE_EQ(r.class_mean[1].ft, 2.0 / 3);
  EXPECT_DOUBLE_EQ(r.class_mean[1].ap, 2.4 / 3);
  EXPECT_DOUBLE_EQ(r.class_mean[2].ap, 0.0);
}

TEST(Retrieval, PrecisionRecallCurveMatchesTheHandComputation) {
  // Precision at the relevant results (k / rank_k), at recall 1/2 and 1:
  //   q0: 1, 2/4   q1: 1, 1   q2: 1/2, 2/3   q3: 1, 2/5   q4: 1, 1   q5: 1, 2/5
  // Interpolated (best precision at recall ≥ level): for levels ≤ 1/2 the larger of the two, above 1/2 the
  // second: q0 1 | 0.5, q1 1 | 1, q2 2/3 | 2/3, q3 1 | 0.4, q4 1 | 1, q5 1 | 0.4.
  RetrievalOptions o;
  o.recall_levels = {0.0, 0.25, 0.5, 0.75, 1.0};
  RetrievalResult r = evaluate_retrieval(hand_matrix(), kLabels, o);
  const double low = (5 + 2.0 / 3) / 6, high = (0.5 + 1 + 2.0 / 3 + 0.4 + 1 + 0.4) / 6;
  ASSERT_EQ(r.pr.precision.size(), 5u);
  EXPECT_DOUBLE_EQ(r.pr.precision[0], low);
  EXPECT_DOUBLE_EQ(r.pr.precision[1], low);
  EXPECT_DOUBLE_EQ(r.pr.precision[2], low);
  EXPECT_DOUBLE_EQ(r.pr.precision[3], high);
  EXPECT_DOUBLE_EQ(r.pr.precision[4], high);
  // Default levels: 0, 0.05, ..., 1 and a non-increasing curve.
  RetrievalResult d = evaluate_retrieval(hand_matrix(), kLabels);
  ASSERT_EQ(d.pr.recall.size(), 21u);
  EXPECT_DOUBLE_EQ(d.pr.recall[10], 0.5);
  for (size_t l = 1; l < d.pr.precision.size(); ++l) EXPECT_LE(d.pr.precision[l], d.pr.precision[l - 1]);
}

TEST(Retrieval, EMeasureDepth) {
  // Looking at the first K = 2 results only: r relevant among them gives e = 2r/(K + R) = 2r/4.
  //   q0: {1, 3} r = 1 → 0.5   q1: {0, 2} r = 2 → 1   q2: {6, 1} r = 1 → 0.5
  //   q3: {4, 0} r = 1 → 0.5   q4: {3, 5} r = 2 → 1   q5: {4, 0} r = 1 → 0.5      mean 4/6
  RetrievalOptions o;
  o.e_measure_depth = 2;
  RetrievalResult r = evaluate_retrieval(hand_matrix(), kLabels, o);
  EXPECT_DOUBLE_EQ(r.queries[1].scores.e, 1.0);
  EXPECT_DOUBLE_EQ(r.queries[2].scores.e, 0.5);
  EXPECT_DOUBLE_EQ(r.mean.e, 4.0 / 6);
}

TEST(Retrieval, SmallClassesAreSkippedAsQueries) {
  // Classes {0, 1} (2 shapes: skipped by default) and {2, 3, 4}.
  //        0    1    2    3    4
  //   0    -    1    2    3    4
  //   1    1    -    5    6    7
  //   2    2    5    -    8    9
  //   3    3    6    8    -   10
  //   4    4    7    9   10    -
  // Query 2 ranks 0 1 3 4: relevant at ranks 3, 4 → nn 0, ft 0, st 1, ap (1/3 + 2/4)/2 = 5/12.
  Eigen::MatrixXd D(5, 5);
  D << 0, 1, 2, 3, 4, 1, 0, 5, 6, 7, 2, 5, 0, 8, 9, 3, 6, 8, 0, 10, 4, 7, 9, 10, 0;
  std::vector<int> labels = {0, 0, 1, 1, 1};
  RetrievalResult r = evaluate_retrieval(D, labels);
  EXPECT_EQ(r.skipped, 2);
  ASSERT_EQ(r.queries.size(), 3u);
  EXPECT_EQ(r.queries[0].query, 2);
  EXPECT_DOUBLE_EQ(r.queries[0].scores.nn, 0.0);
  EXPECT_DOUBLE_EQ(r.queries[0].scores.ft, 0.0);
  EXPECT_DOUBLE_EQ(r.queries[0].scores.st, 1.0);
  EXPECT_DOUBLE_EQ(r.queries[0].scores.ap, 5.0 / 12);
  // With min_class_size 2 the pair's shapes are queries too (R = 1): query 0 finds 1 first.
  RetrievalOptions o;
  o.min_class_size = 2;
  RetrievalResult all = evaluate_retrieval(D, labels, o);
  EXPECT_EQ(all.skipped, 0);
  EXPECT_DOUBLE_EQ(all.queries[0].scores.ap, 1.0);
  o.min_class_size = 4;
  EXPECT_THROW(evaluate_retrieval(D, labels, o), Error);
}

TEST(Retrieval, PerfectAndInvalidInput) {
  // Distances 0 within a class and 1 across: every measure is 1 except E (K = 5, R = 2: 2·2/7).
  std::vector<int> labels = {0, 0, 0, 1, 1, 1};
  Eigen::MatrixXd D(6, 6);
  for (int i = 0; i < 6; ++i)
    for (int j = 0; j < 6; ++j)
      D(i, j) = labels[static_cast<size_t>(i)] == labels[static_cast<size_t>(j)] ? 0.0 : 1.0;
  RetrievalResult r = evaluate_retrieval(D, labels);
  EXPECT_DOUBLE_EQ(r.mean.nn, 1);
  EXPECT_DOUBLE_EQ(r.mean.ft, 1);
  EXPECT_DOUBLE_EQ(r.mean.st, 1);
  EXPECT_DOUBLE_EQ(r.mean.dcg, 1);
  EXPECT_DOUBLE_EQ(r.mean.ap, 1);
  EXPECT_DOUBLE_EQ(r.mean.e, 4.0 / 7);
  for (double p : r.pr.precision) EXPECT_DOUBLE_EQ(p, 1.0);
  EXPECT_THROW(evaluate_retrieval(D.topRows(5), labels), Error);
  EXPECT_THROW(evaluate_retrieval(D, {0, 0, 0}), Error);
  Eigen::MatrixXd bad = D;
  bad(0, 1) = std::nan("");
  EXPECT_THROW(evaluate_retrieval(bad, labels), Error);
}

TEST(Retrieval, DistanceMatrixImageAndConfusion) {
  // Nearest neighbours (from the matrix above): 0→1, 1→0, 2→6, 3→4, 4→3, 5→4, 6→2.
  std::vector<int> labels = {1, 0, 0, 1, 1, 0, 2};  // shuffled classes to exercise the ordering
  Eigen::MatrixXd D = hand_matrix();
  DistanceMatrixImage image = distance_matrix_image(D, labels);
  EXPECT_EQ(image.order, (std::vector<int>{1, 2, 5, 0, 3, 4, 6}));
  EXPECT_EQ(image.class_starts, (std::vector<int>{0, 3, 6, 7}));
  EXPECT_DOUBLE_EQ(image.values(0, 1), D(1, 2) / 19.0);  // normalised by the largest distance, 19
  EXPECT_DOUBLE_EQ(image.values.maxCoeff(), 1.0);
  // The queries' nearest neighbours (class in brackets): 0(1)→1(0), 1(0)→0(1), 2(0)→6(2), 3(1)→4(1),
  // 4(1)→3(1), 5(0)→4(1); rows the query's class, columns the neighbour's: class 0 (1, 2, 5): →1, →2, →1 =
  // (0, 2, 1); class 1 (0, 3, 4): →0, →1, →1 = (1, 2, 0); class 2 (shape 6 alone) has no query: a zero row.
  Eigen::MatrixXi expected(3, 3);
  expected << 0, 2, 1,  //
      1, 2, 0,          //
      0, 0, 0;
  const RetrievalResult r = evaluate_retrieval(D, labels);
  EXPECT_EQ(r.confusion, expected);
  // Its diagonal over the queries is NN.
  EXPECT_DOUBLE_EQ(r.confusion.trace() / static_cast<double>(r.queries.size()), r.mean.nn);
  // Mean distance between class 2 (shape 6) and class 0 (shapes 1, 2, 5): (11 + 0.5 + 19)/3.
  EXPECT_DOUBLE_EQ(image.class_mean_distance(2, 0), (11 + 0.5 + 19) / 3.0);
  EXPECT_TRUE(std::isnan(image.class_mean_distance(2, 2)));  // a single shape: no pair
}

TEST(Retrieval, LabelsFromClassNames) {
  std::vector<std::string> names;
  EXPECT_EQ(labels_from_classes({"cat", "dog", "cat", "man"}, &names), (std::vector<int>{0, 1, 0, 2}));
  EXPECT_EQ(names, (std::vector<std::string>{"cat", "dog", "man"}));
}

TEST(EvaluateCli, WritesMetricsFromANamedMatrix) {
  // The hand matrix with names whose prefixes give the classes (man0 alone: skipped as a query).
  std::string dir = test::scratch_dir("evaluate");
  write_distance_csv(dir + "/d.csv", {"cat0", "cat1", "cat2", "dog0", "dog1", "dog2", "man0"}, hand_matrix());
  test::CliResult r = test::run_cli("evaluate '" + dir + "/d.csv' --out '" + dir + "/out' --json -q");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  nlohmann::json m = nlohmann::json::parse(r.out);
  EXPECT_NEAR(m["map"].get<double>(), (0.75 + 1 + 7.0 / 12 + 0.7 + 1 + 0.7) / 6, 1e-12);
  EXPECT_NEAR(m["nn"].get<double>(), 5.0 / 6, 1e-12);
  EXPECT_NEAR(m["ft"].get<double>(), 4.0 / 6, 1e-12);
  EXPECT_NEAR(m["st"].get<double>(), 5.0 / 6, 1e-12);
  EXPECT_NEAR(m["e"].get<double>(), 0.5, 1e-12);
  EXPECT_EQ(m["pr"]["recall"].size(), 21u);
  EXPECT_EQ(m["skipped"].get<int>(), 1);
  for (const char* file : {"metrics.json", "pr.csv", "queries.csv", "matrix.csv", "confusion.csv"})
    EXPECT_TRUE(std::filesystem::exists(dir + "/out/" + file)) << file;
  // The confusion matrix says what its rows and columns are.
  EXPECT_EQ(read_file(dir + "/out/confusion.csv"),
            "query class / nearest neighbour class,cat,dog,man\ncat,2,0,1\ndog,0,3,0\n");  // man0: no query
  // Its figures, drawn when Python has matplotlib; otherwise a warning says why.
  if (find_python("matplotlib, numpy").empty()) {
    EXPECT_NE(r.err.find("no figures"), std::string::npos) << r.err;
  } else {
    for (const char* file : {"pr.png", "confusion.png", "matrix.png"})
      EXPECT_GT(std::filesystem::file_size(dir + "/out/" + file), 1000u) << file << r.err;
  }
  // Labels from a file override the names: all seven in one class → every result relevant.
  test::write_text(dir + "/labels.csv", "a\na\na\na\na\na\na\n");
  r = test::run_cli("evaluate '" + dir + "/d.csv' --labels '" + dir + "/labels.csv' --out '" + dir +
                    "/out2' --json -q --no-draw");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_FALSE(std::filesystem::exists(dir + "/out2/pr.png"));
  EXPECT_NEAR(nlohmann::json::parse(r.out)["map"].get<double>(), 1.0, 1e-12);
  // The summary says why a shape is not a query (man0: a class of one).
  r = test::run_cli("evaluate '" + dir + "/d.csv' --out '" + dir + "/out4' -q --no-draw");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.out.find("6 queries (1 skipped: their class has fewer than 3 shapes; --min-class-size)"),
            std::string::npos)
      << r.out;
  // A broken file: a one-line error, non-zero exit.
  test::write_text(dir + "/bad.csv", "a,b\n0,1\n");
  r = test::run_cli("evaluate '" + dir + "/bad.csv' --out '" + dir + "/out3' -q");
  EXPECT_NE(r.exit_code, 0);
  EXPECT_NE(r.err.find("bad.csv"), std::string::npos);
  std::filesystem::remove_all(dir);
}

}  // namespace retrieval_test
// One query against a database (the noise experiment's queries): the rule of evaluate_retrieval.
TEST(Retrieval, AveragePrecisionOfOneQueryKnownAnswers) {
  // Ranked: index 1 (irrelevant), 2 (relevant, rank 2), 0 (relevant, rank 3): AP = (1/2 + 2/3) / 2.
  bool nn = true;
  EXPECT_NEAR(average_precision({3, 1, 2}, {1, 0, 1}, &nn), (0.5 + 2.0 / 3) / 2, 1e-15);
  EXPECT_FALSE(nn);
  EXPECT_DOUBLE_EQ(average_precision({1, 2, 3}, {1, 1, 0}, &nn), 1.0);
  EXPECT_TRUE(nn);
  // Ties go to the smaller index (eval/retrieval.h): the irrelevant index 0 comes first.
  EXPECT_DOUBLE_EQ(average_precision({1, 1}, {0, 1}, &nn), 0.5);
  EXPECT_FALSE(nn);
  EXPECT_EQ(average_precision({1, 2}, {0, 0}), -1.0);  // nothing relevant
  EXPECT_THROW(average_precision({1, 2}, {0}), Error);
}

}  // namespace cshapes

namespace cshapes {
namespace retrieval_test {

// Per-class measures (class_mean) of a hand-made matrix, each ranking chosen, every value worked out by
// hand from the definitions (eval/retrieval.h): classes A = {0, 1, 2}, B = {3, 4, 5}, R = 2, K = 5.
TEST(Retrieval, PerClassMeasuresMatchTheHandComputation) {
  const std::vector<std::vector<int>> rankings = {
      {1, 3, 2, 4, 5},  // a0: relevant at ranks 1, 3
      {3, 4, 0, 2, 5},  // a1: 3, 4
      {0, 1, 3, 4, 5},  // a2: 1, 2
      {4, 5, 0, 1, 2},  // b0: 1, 2
      {0, 3, 5, 1, 2},  // b1: 2, 3
      {0, 1, 2, 3, 4},  // b2: 4, 5
  };
  Eigen::MatrixXd D = Eigen::MatrixXd::Zero(6, 6);
  for (int q = 0; q < 6; ++q)
    for (int k = 0; k < 5; ++k) D(q, rankings[static_cast<size_t>(q)][static_cast<size_t>(k)]) = k + 1;
  const RetrievalResult r = evaluate_retrieval(D, {0, 0, 0, 1, 1, 1});
  const double l3 = 1 / std::log2(3.0), l5 = 1 / std::log2(5.0);
  const double e = 2.0 * 2 / (5 + 2);  // every query has both relevant results among the first 5
  // Class A: queries a0 (1, 3), a1 (3, 4), a2 (1, 2).
  const RetrievalScores& a = r.class_mean[0];
  EXPECT_NEAR(a.nn, 2.0 / 3, 1e-12);
  EXPECT_NEAR(a.ft, (0.5 + 0 + 1) / 3, 1e-12);
  EXPECT_NEAR(a.st, 1.0, 1e-12);
  EXPECT_NEAR(a.e, e, 1e-12);
  EXPECT_NEAR(a.dcg, ((1 + l3) / 2 + (l3 + 0.5) / 2 + 1) / 3, 1e-12);
  EXPECT_NEAR(a.ap, ((1 + 2.0 / 3) / 2 + (1.0 / 3 + 2.0 / 4) / 2 + 1) / 3, 1e-12);
  // Class B: queries b0 (1, 2), b1 (2, 3), b2 (4, 5).
  const RetrievalScores& b = r.class_mean[1];
  EXPECT_NEAR(b.nn, 1.0 / 3, 1e-12);
  EXPECT_NEAR(b.ft, (1 + 0.5 + 0) / 3, 1e-12);
  EXPECT_NEAR(b.st, (1 + 1 + 0.5) / 3, 1e-12);
  EXPECT_NEAR(b.e, e, 1e-12);
  EXPECT_NEAR(b.dcg, (1 + (1 + l3) / 2 + (0.5 + l5) / 2) / 3, 1e-12);
  EXPECT_NEAR(b.ap, (1 + (0.5 + 2.0 / 3) / 2 + (0.25 + 0.4) / 2) / 3, 1e-12);
  EXPECT_EQ(r.class_queries, (std::vector<int>{3, 3}));
  // Equal classes: the micro average is the mean of the class means.
  EXPECT_NEAR(r.mean.ap, (a.ap + b.ap) / 2, 1e-12);
  EXPECT_NEAR(r.mean.dcg, (a.dcg + b.dcg) / 2, 1e-12);
}

}  // namespace retrieval_test
}  // namespace cshapes
