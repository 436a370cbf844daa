#include "cshapes/eval/retrieval.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <functional>
#include <limits>
#include <map>
#include <numeric>
#include <random>

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
  Eigen::MatrixXd expected(3, 3);
  expected << 0, 2, 1,  //
      1, 2, 0,          //
      0, 0, 0;
  const RetrievalResult r = evaluate_retrieval(D, labels);
  EXPECT_EQ(r.confusion, expected);
  // Its diagonal over the queries is NN.
  EXPECT_DOUBLE_EQ(r.confusion.trace() / static_cast<double>(r.queries.size()), r.mean.nn);
  EXPECT_EQ(r.tied_queries, 0);  // all distances distinct
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
  // Labels from a file override the names (here cat2 and dog2 swap classes), and metrics.json says so.
  test::write_text(dir + "/labels.csv", "cat\ncat\ndog\ndog\ndog\ncat\nman\n");
  r = test::run_cli("evaluate '" + dir + "/d.csv' --labels '" + dir + "/labels.csv' --out '" + dir +
                    "/out2' --json -q --no-draw");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_FALSE(std::filesystem::exists(dir + "/out2/pr.png"));
  EXPECT_EQ(nlohmann::json::parse(r.out)["classes_from"], dir + "/labels.csv");
  EXPECT_EQ(nlohmann::json::parse(r.out)["classes"]["cat"]["queries"].get<int>(), 3);
  // All seven in one class: every result would be relevant (mAP 1.0 said nothing): refused, exit 1.
  test::write_text(dir + "/one.csv", "a\na\na\na\na\na\na\n");
  r = test::run_cli("evaluate '" + dir + "/d.csv' --labels '" + dir + "/one.csv' --out '" + dir +
                    "/out5' -q --no-draw");
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.err.find("all 7 shapes have class 'a'"), std::string::npos) << r.err;
  EXPECT_FALSE(std::filesystem::exists(dir + "/out5/metrics.json"));
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
  double nn = -1;
  EXPECT_NEAR(average_precision({3, 1, 2}, {1, 0, 1}, &nn), (0.5 + 2.0 / 3) / 2, 1e-15);
  EXPECT_EQ(nn, 0.0);
  EXPECT_DOUBLE_EQ(average_precision({1, 2, 3}, {1, 1, 0}, &nn), 1.0);
  EXPECT_EQ(nn, 1.0);
  // A tie (eval/retrieval.h): the relevant entry is first or second with probability 1/2 each, so AP is
  // (1/1 + 1/2)/2 and nn 1/2, whichever index it has; one ulp apart is no tie.
  EXPECT_DOUBLE_EQ(average_precision({1, 1}, {0, 1}, &nn), 0.75);
  EXPECT_EQ(nn, 0.5);
  EXPECT_DOUBLE_EQ(average_precision({1, 1}, {1, 0}, &nn), 0.75);
  EXPECT_EQ(nn, 0.5);
  EXPECT_DOUBLE_EQ(average_precision({1, std::nextafter(1.0, 2.0)}, {0, 1}, &nn), 0.5);
  EXPECT_EQ(nn, 0.0);
  const double inf = std::numeric_limits<double>::infinity();
  EXPECT_DOUBLE_EQ(average_precision({inf, 1, inf}, {1, 0, 0}, &nn), (1.0 / 2 + 1.0 / 3) / 2);  // inf == inf
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

namespace cshapes {
namespace retrieval_test {

const double kInf = std::numeric_limits<double>::infinity();

// The reference for ties, a second code path: the measures of a ranking without ties, straight from the
// definitions (eval/retrieval.h), averaged over every arrangement of the classes within each run of equal
// distances. Each distinct arrangement stands for the same number of orders of the tied shapes, so their mean
// is the mean over all orders.
struct Reference {
  RetrievalScores scores;
  std::vector<double> precision;        // E[k / rank_k], k = 1..R
  std::map<int, double> nearest_class;  // probability that the first result has this class
};

void add_untied(const std::vector<int>& ranked_classes, int query_class, int depth, double weight,
                Reference& out) {
  const int relevant_total =
      static_cast<int>(std::count(ranked_classes.begin(), ranked_classes.end(), query_class));
  int found = 0;
  double ft = 0, st = 0, e = 0, dcg = 0;
  std::vector<double> precision;
  for (int rank = 1; rank <= static_cast<int>(ranked_classes.size()); ++rank) {
    if (ranked_classes[static_cast<size_t>(rank - 1)] != query_class) continue;
    ++found;
    precision.push_back(static_cast<double>(found) / rank);
    ft += rank <= relevant_total;
    st += rank <= 2 * relevant_total;
    e += rank <= depth;
    dcg += rank == 1 ? 1.0 : 1.0 / std::log2(rank);
  }
  double ideal = 1;
  for (int i = 2; i <= relevant_total; ++i) ideal += 1.0 / std::log2(i);
  double ap = 0;
  for (double p : precision) ap += p / relevant_total;
  RetrievalScores& s = out.scores;
  s.nn += weight * (ranked_classes.front() == query_class);
  s.ft += weight * ft / relevant_total;
  s.st += weight * st / relevant_total;
  s.e += weight * (e > 0 ? 2 * e / (depth + relevant_total) : 0.0);
  s.dcg += weight * dcg / ideal;
  s.ap += weight * ap;
  out.precision.resize(precision.size(), 0.0);
  for (size_t k = 0; k < precision.size(); ++k) out.precision[k] += weight * precision[k];
  out.nearest_class[ranked_classes.front()] += weight;
}

Reference brute_force_expectation(const std::vector<double>& distances, const std::vector<int>& classes,
                                  int query_class, int depth) {
  std::vector<size_t> order(distances.size());
  std::iota(order.begin(), order.end(), 0);
  std::sort(order.begin(), order.end(), [&](size_t a, size_t b) { return distances[a] < distances[b]; });
  std::vector<int> ranked;
  std::vector<size_t> group_starts;
  for (size_t k = 0; k < order.size(); ++k) {
    if (k == 0 || distances[order[k]] != distances[order[k - 1]]) group_starts.push_back(k);
    ranked.push_back(classes[order[k]]);
  }
  group_starts.push_back(order.size());
  for (size_t g = 0; g + 1 < group_starts.size(); ++g)
    std::sort(ranked.begin() + static_cast<long>(group_starts[g]),
              ranked.begin() + static_cast<long>(group_starts[g + 1]));
  std::vector<std::vector<int>> arrangements;
  std::function<void(size_t)> arrange = [&](size_t g) {
    if (g + 1 == group_starts.size()) {
      arrangements.push_back(ranked);
      return;
    }
    auto first = ranked.begin() + static_cast<long>(group_starts[g]);
    auto last = ranked.begin() + static_cast<long>(group_starts[g + 1]);
    do arrange(g + 1);
    while (std::next_permutation(first, last));
  };
  arrange(0);
  Reference reference;
  for (const std::vector<int>& a : arrangements)
    add_untied(a, query_class, depth, 1.0 / static_cast<double>(arrangements.size()), reference);
  return reference;
}

// Every measure evaluate_retrieval gives, query by query, the PR curve and the confusion matrix against the
// brute-force expectation.
void expect_expectations(const Eigen::MatrixXd& D, const std::vector<int>& labels,
                         const RetrievalOptions& options = {}) {
  const RetrievalResult r = evaluate_retrieval(D, labels, options);
  const int n = static_cast<int>(D.rows());
  const int depth = std::min(options.e_measure_depth, n - 1);
  std::vector<double> pr(r.pr.recall.size(), 0.0);
  Eigen::MatrixXd confusion = Eigen::MatrixXd::Zero(r.confusion.rows(), r.confusion.cols());
  for (const QueryResult& q : r.queries) {
    std::vector<double> distances;
    std::vector<int> classes;
    for (int j = 0; j < n; ++j)
      if (j != q.query) {
        distances.push_back(D(q.query, j));
        classes.push_back(labels[static_cast<size_t>(j)]);
      }
    const Reference ref = brute_force_expectation(distances, classes, q.label, depth);
    const RetrievalScores& s = q.scores;
    EXPECT_NEAR(s.nn, ref.scores.nn, 1e-12) << "query " << q.query;
    EXPECT_NEAR(s.ft, ref.scores.ft, 1e-12) << "query " << q.query;
    EXPECT_NEAR(s.st, ref.scores.st, 1e-12) << "query " << q.query;
    EXPECT_NEAR(s.e, ref.scores.e, 1e-12) << "query " << q.query;
    EXPECT_NEAR(s.dcg, ref.scores.dcg, 1e-12) << "query " << q.query;
    EXPECT_NEAR(s.ap, ref.scores.ap, 1e-12) << "query " << q.query;
    const double R = static_cast<double>(ref.precision.size());
    for (size_t l = 0; l < pr.size(); ++l) {
      double best = 0;
      for (size_t k = 1; k <= ref.precision.size(); ++k)
        if (static_cast<double>(k) / R >= r.pr.recall[l] - 1e-12) best = std::max(best, ref.precision[k - 1]);
      pr[l] += best / static_cast<double>(r.queries.size());
    }
    for (const auto& [c, share] : ref.nearest_class) confusion(q.label, c) += share;
  }
  for (size_t l = 0; l < pr.size(); ++l) EXPECT_NEAR(r.pr.precision[l], pr[l], 1e-12) << "level " << l;
  EXPECT_LT((r.confusion - confusion).cwiseAbs().maxCoeff(), 1e-12);
}

// McSherry & Najork (2008), a third path: the expected AP of a query whose n results are all tied, r of them
// relevant, is (1/r) Σ_{i=1..n} [r/n + (i − 1)·r(r − 1)/(n(n − 1))] / i.
double expected_ap_all_tied(int n, int r) {
  double sum = 0;
  for (int i = 1; i <= n; ++i)
    sum += (static_cast<double>(r) / n + (i - 1.0) * r * (r - 1) / (static_cast<double>(n) * (n - 1))) / i;
  return sum / r;
}

// Issue 57: twelve shapes of three classes at one distance gave mAP 0.505 and NN 0.333 by index order (the
// class listed first 1.0, the last 0.195). Ranked at random, each query finds its 3 relevant among 11.
TEST(RetrievalTies, AConstantMatrixGivesTheExpectationOfRandomRanking) {
  const std::vector<int> labels = {0, 0, 0, 0, 1, 1, 1, 1, 2, 2, 2, 2};
  const Reference reference =
      brute_force_expectation(std::vector<double>(11, 1.0), {0, 0, 0, 1, 1, 1, 1, 2, 2, 2, 2}, 0, 11);
  // 1e-12: the brute force sums 11!/(3!·4!·4!) = 11,550 arrangements, each rounded.
  EXPECT_NEAR(reference.scores.ap, expected_ap_all_tied(11, 3), 1e-12);
  for (double value : {0.0, 5.0, kInf}) {
    const Eigen::MatrixXd D = Eigen::MatrixXd::Constant(12, 12, value);
    const RetrievalResult r = evaluate_retrieval(D, labels);
    EXPECT_NEAR(r.mean.ap, reference.scores.ap, 1e-12) << value;
    EXPECT_NEAR(r.mean.nn, 3.0 / 11, 1e-15) << value;
    EXPECT_NEAR(r.mean.ft, 3.0 / 11, 1e-15) << value;
    for (int c = 0; c < 3; ++c) EXPECT_NEAR(r.class_mean[static_cast<size_t>(c)].ap, r.mean.ap, 1e-15);
    EXPECT_EQ(r.tied_queries, 12);
    // Each query's nearest: its own class with probability 3/11, each other class 4/11.
    for (int a = 0; a < 3; ++a)
      for (int b = 0; b < 3; ++b) EXPECT_NEAR(r.confusion(a, b), 4 * (a == b ? 3.0 : 4.0) / 11, 1e-14);
    expect_expectations(D, labels);
  }
}

// Matrices with many ties (four values, inf among them, not symmetric), classes of 3, 2 and 1: every
// measure, the PR curve and the confusion matrix are the expectations over all orders of the tied results.
TEST(RetrievalTies, EveryMeasureIsTheExpectationOverTheOrdersOfTiedResults) {
  std::mt19937 random(57);
  const double values[] = {1.0, 2.0, 3.0, kInf};
  const std::vector<int> labels = {0, 0, 0, 1, 1, 1, 2, 2, 3};
  for (int trial = 0; trial < 20; ++trial) {
    Eigen::MatrixXd D(9, 9);
    for (int i = 0; i < 9; ++i)
      for (int j = 0; j < 9; ++j) D(i, j) = i == j ? 0.0 : values[random() % 4];
    RetrievalOptions options;
    options.e_measure_depth = 1 + trial % 5;  // cuts through tie groups
    options.min_class_size = 2 + trial % 2;   // class 2 (two shapes): queries with R = 1, or results only
    expect_expectations(D, labels, options);
  }
}

// The rule for ties makes the measures a function of the matrix, not of the order of its rows.
TEST(RetrievalTies, TheMeasuresDoNotDependOnTheShapesOrder) {
  std::mt19937 random(7);
  const std::vector<int> labels = {0, 0, 0, 1, 1, 1, 1, 2, 2, 2};
  const int n = static_cast<int>(labels.size());
  Eigen::MatrixXd D(n, n);
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j) D(i, j) = i == j ? 0.0 : static_cast<double>(random() % 3);
  std::vector<int> permutation(static_cast<size_t>(n));
  std::iota(permutation.begin(), permutation.end(), 0);
  std::shuffle(permutation.begin(), permutation.end(), random);
  Eigen::MatrixXd P(n, n);
  std::vector<int> permuted_labels;
  for (int i = 0; i < n; ++i) {
    permuted_labels.push_back(labels[static_cast<size_t>(permutation[static_cast<size_t>(i)])]);
    for (int j = 0; j < n; ++j)
      P(i, j) = D(permutation[static_cast<size_t>(i)], permutation[static_cast<size_t>(j)]);
  }
  const RetrievalResult a = evaluate_retrieval(D, labels), b = evaluate_retrieval(P, permuted_labels);
  ASSERT_GT(a.tied_queries, 0);
  ASSERT_EQ(a.queries.size(), b.queries.size());
  for (const QueryResult& q : b.queries) {
    const QueryResult& original = a.queries[static_cast<size_t>(permutation[static_cast<size_t>(q.query)])];
    EXPECT_EQ(q.scores.ap, original.scores.ap) << q.query;
    EXPECT_EQ(q.scores.nn, original.scores.nn) << q.query;
    EXPECT_EQ(q.scores.ft, original.scores.ft) << q.query;
    EXPECT_EQ(q.scores.dcg, original.scores.dcg) << q.query;
  }
  EXPECT_NEAR(a.mean.ap, b.mean.ap, 1e-15);
  for (size_t l = 0; l < a.pr.precision.size(); ++l) EXPECT_NEAR(a.pr.precision[l], b.pr.precision[l], 1e-15);
}

// One class: every result relevant, every measure 1 whatever the distances: refused, not reported as 1.0.
TEST(RetrievalTies, OneClassIsRefused) {
  try {
    evaluate_retrieval(Eigen::MatrixXd::Constant(9, 9, 1.0), std::vector<int>(9, 0));
    ADD_FAILURE() << "no error";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("one class"), std::string::npos) << e.what();
  }
}

// Issue 57: the README's pipeline on a manifest whose file names carry no class (s0 … s8): evaluate took
// them all for class "s" and said mAP 1.000. Refused, with where classes come from; the labels file distmat
// writes beside the matrix is read.
TEST(EvaluateCli, ClassesFromTheLabelsFileBesideTheMatrixElseOneClassIsRefused) {
  const std::string dir = test::scratch_dir("evaluate_labels");
  std::vector<std::string> names, classes;
  Eigen::MatrixXd D(9, 9);
  for (int i = 0; i < 9; ++i) {
    names.push_back("s" + std::to_string(i));
    classes.push_back(std::string(1, static_cast<char>('a' + i / 3)));
    for (int j = 0; j < 9; ++j) D(i, j) = i == j ? 0.0 : (i / 3 == j / 3 ? 1.0 : 2.0) + 0.01 * (i + j);
  }
  write_distance_csv(dir + "/D.csv", names, D);
  test::CliResult r = test::run_cli("evaluate '" + dir + "/D.csv' --out '" + dir + "/out' -q --no-draw");
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.err.find("all 9 shapes have class 's' (from their names"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("--labels"), std::string::npos) << r.err;
  EXPECT_FALSE(std::filesystem::exists(dir + "/out/metrics.json"));
  EXPECT_EQ(labels_path_for(dir + "/D.csv"), dir + "/D.labels.csv");
  write_labels_csv(labels_path_for(dir + "/D.csv"), names, classes);
  EXPECT_EQ(read_file(dir + "/D.labels.csv").substr(0, 20), "name,class\ns0,a\ns1,a");
  r = test::run_cli("evaluate '" + dir + "/D.csv' --out '" + dir + "/out' --json --no-draw");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.err.find("classes from " + dir + "/D.labels.csv"), std::string::npos) << r.err;
  const nlohmann::json m = nlohmann::json::parse(r.out);
  EXPECT_EQ(m["classes_from"], dir + "/D.labels.csv");
  EXPECT_EQ(m["classes"].size(), 3u);
  EXPECT_NEAR(m["map"].get<double>(), 1.0, 1e-12);
  EXPECT_EQ(m["tied_queries"], 0);
  std::filesystem::remove_all(dir);
}

// The report says when ties were met and what was done with them; confusion.csv holds the shares.
TEST(EvaluateCli, TiesAreSaidAndTheConfusionHoldsShares) {
  const std::string dir = test::scratch_dir("evaluate_ties");
  std::vector<std::string> names;
  for (const char* c : {"a", "b", "c"})
    for (int k = 0; k < 4; ++k) names.push_back(c + std::to_string(k));
  write_distance_csv(dir + "/D.csv", names, Eigen::MatrixXd::Zero(12, 12));
  test::CliResult r = test::run_cli("evaluate '" + dir + "/D.csv' --out '" + dir + "/out' --no-draw");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.out.find("mAP 0.420   NN 0.273"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("12 queries have tied distances: their measures are expected values"),
            std::string::npos)
      << r.out;
  const nlohmann::json m = nlohmann::json::parse(read_file(dir + "/out/metrics.json"));
  EXPECT_NE(m["conventions"].get<std::string>().find("McSherry & Najork"), std::string::npos);
  EXPECT_EQ(read_file(dir + "/out/confusion.csv"),
            "query class / nearest neighbour class,a,b,c\n"
            "a,1.090909091,1.454545455,1.454545455\nb,1.454545455,1.090909091,1.454545455\n"
            "c,1.454545455,1.454545455,1.090909091\n");
  std::filesystem::remove_all(dir);
}

}  // namespace retrieval_test
}  // namespace cshapes
