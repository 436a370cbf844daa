#include "cshapes/eval/retrieval.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <numeric>

#include "cshapes/support/error.h"

namespace cshapes {

namespace {

void check_input(const Eigen::MatrixXd& D, const std::vector<int>& labels) {
  CSHAPES_REQUIRE(D.rows() == D.cols(), "retrieval: the distance matrix must be square, got ", D.rows(), "x",
                  D.cols());
  CSHAPES_REQUIRE(D.rows() >= 2, "retrieval: need at least 2 shapes, got ", D.rows());
  CSHAPES_REQUIRE(static_cast<Index>(labels.size()) == D.rows(), "retrieval: ", labels.size(), " labels for ",
                  D.rows(), " shapes");
  for (size_t i = 0; i < labels.size(); ++i)
    CSHAPES_REQUIRE(labels[i] >= 0, "retrieval: label of shape ", i, " is negative (", labels[i], ")");
  for (Index i = 0; i < D.rows(); ++i)
    for (Index j = 0; j < D.cols(); ++j)
      CSHAPES_REQUIRE(!std::isnan(D(i, j)), "retrieval: distance (", i, ", ", j, ") is NaN");
}

std::vector<int> rank_others(const Eigen::MatrixXd& D, int query) {
  std::vector<int> ranking;
  ranking.reserve(static_cast<size_t>(D.rows() - 1));
  for (int j = 0; j < D.rows(); ++j)
    if (j != query) ranking.push_back(j);
  std::stable_sort(ranking.begin(), ranking.end(), [&](int a, int b) { return D(query, a) < D(query, b); });
  return ranking;
}

// Average precision from the precisions at the ranks of the relevant results, in rank order (every relevant
// result found, so their count is R): one summation order for every caller, so results agree to the bit.
double mean_of_precisions(const std::vector<double>& precision_at_relevant) {
  return std::accumulate(precision_at_relevant.begin(), precision_at_relevant.end(), 0.0) /
         static_cast<double>(precision_at_relevant.size());
}

}  // namespace

RetrievalResult evaluate_retrieval(const Eigen::MatrixXd& D, const std::vector<int>& labels,
                                   const RetrievalOptions& options) {
  check_input(D, labels);
  CSHAPES_REQUIRE(options.e_measure_depth >= 1, "retrieval: e_measure_depth must be >= 1");
  const int n = static_cast<int>(D.rows());
  const int num_classes = *std::max_element(labels.begin(), labels.end()) + 1;
  std::vector<int> class_size(static_cast<size_t>(num_classes), 0);
  for (int label : labels) ++class_size[static_cast<size_t>(label)];

  RetrievalResult result;
  result.pr.recall = options.recall_levels;
  if (result.pr.recall.empty())
    for (int k = 0; k <= 20; ++k) result.pr.recall.push_back(k / 20.0);
  for (double r : result.pr.recall)
    CSHAPES_REQUIRE(r >= 0 && r <= 1, "retrieval: recall level ", r, " is outside [0, 1]");
  result.pr.precision.assign(result.pr.recall.size(), 0.0);
  result.class_mean.assign(static_cast<size_t>(num_classes), RetrievalScores{});
  result.class_queries.assign(static_cast<size_t>(num_classes), 0);
  result.confusion = Eigen::MatrixXi::Zero(num_classes, num_classes);

  const int depth = std::min(options.e_measure_depth, n - 1);
  for (int q = 0; q < n; ++q) {
    const int label = labels[static_cast<size_t>(q)];
    const int relevant_total = class_size[static_cast<size_t>(label)] - 1;  // R = C − 1
    if (class_size[static_cast<size_t>(label)] < std::max(options.min_class_size, 2)) {
      ++result.skipped;
      continue;
    }
    QueryResult query;
    query.query = q;
    query.label = label;
    query.ranking = rank_others(D, q);
    RetrievalScores& s = query.scores;
    int found = 0;  // relevant results so far
    double dcg = 0;
    std::vector<double> precision_at_relevant;  // p_k = k / rank_k
    for (int rank = 1; rank <= n - 1; ++rank) {
      bool relevant = labels[static_cast<size_t>(query.ranking[static_cast<size_t>(rank - 1)])] == label;
      if (!relevant) continue;
      ++found;
      precision_at_relevant.push_back(static_cast<double>(found) / rank);
      if (rank == 1) s.nn = 1;
      if (rank <= relevant_total) s.ft += 1;
      if (rank <= 2 * relevant_total) s.st += 1;
      if (rank <= depth) s.e += 1;
      dcg += rank == 1 ? 1.0 : 1.0 / std::log2(static_cast<double>(rank));
    }
    const double R = relevant_total;
    s.ft /= R;
    s.st /= R;
    s.e = s.e > 0 ? 2 * s.e / (depth + R) : 0.0;  // 2/(1/P + 1/R) with P = r/K, R = r/(C−1)
    double ideal = 1;
    for (int i = 2; i <= relevant_total; ++i) ideal += 1.0 / std::log2(static_cast<double>(i));
    s.dcg = dcg / ideal;
    s.ap = mean_of_precisions(precision_at_relevant);

    // Interpolated precision at each recall level: the best precision at recall ≥ the level.
    for (size_t l = 0; l < result.pr.recall.size(); ++l) {
      double best = 0;
      for (int k = 1; k <= relevant_total; ++k)
        if (static_cast<double>(k) / R >= result.pr.recall[l] - 1e-12)
          best = std::max(best, precision_at_relevant[static_cast<size_t>(k - 1)]);
      result.pr.precision[l] += best;
    }
    RetrievalScores& c = result.class_mean[static_cast<size_t>(label)];
    c.nn += s.nn, c.ft += s.ft, c.st += s.st, c.e += s.e, c.dcg += s.dcg, c.ap += s.ap;
    ++result.class_queries[static_cast<size_t>(label)];
    ++result.confusion(label, labels[static_cast<size_t>(query.ranking.front())]);
    result.queries.push_back(std::move(query));
  }
  CSHAPES_REQUIRE(!result.queries.empty(), "retrieval: no class has at least ", options.min_class_size,
                  " shapes, so there is no query to evaluate");

  const double num_queries = static_cast<double>(result.queries.size());
  RetrievalScores& m = result.mean;
  for (const QueryResult& q : result.queries) {
    m.nn += q.scores.nn, m.ft += q.scores.ft, m.st += q.scores.st;
    m.e += q.scores.e, m.dcg += q.scores.dcg, m.ap += q.scores.ap;
  }
  m.nn /= num_queries, m.ft /= num_queries, m.st /= num_queries;
  m.e /= num_queries, m.dcg /= num_queries, m.ap /= num_queries;
  for (double& p : result.pr.precision) p /= num_queries;
  for (size_t c = 0; c < result.class_mean.size(); ++c) {
    double k = result.class_queries[c];
    if (k == 0) continue;
    RetrievalScores& s = result.class_mean[c];
    s.nn /= k, s.ft /= k, s.st /= k, s.e /= k, s.dcg /= k, s.ap /= k;
  }
  return result;
}

double average_precision(const std::vector<double>& distances, const std::vector<char>& relevant,
                         bool* nearest_relevant) {
  CSHAPES_REQUIRE(distances.size() == relevant.size(), "average_precision: ", distances.size(),
                  " distances but ", relevant.size(), " relevance flags");
  std::vector<int> order(distances.size());
  std::iota(order.begin(), order.end(), 0);
  std::stable_sort(order.begin(), order.end(), [&](int a, int b) { return distances[a] < distances[b]; });
  std::vector<double> precision_at_relevant;
  for (size_t rank = 1; rank <= order.size(); ++rank)
    if (relevant[order[rank - 1]])
      precision_at_relevant.push_back(static_cast<double>(precision_at_relevant.size() + 1) / rank);
  if (nearest_relevant) *nearest_relevant = !order.empty() && relevant[order[0]];
  return precision_at_relevant.empty() ? -1.0 : mean_of_precisions(precision_at_relevant);
}

std::vector<int> labels_from_classes(const std::vector<std::string>& classes,
                                     std::vector<std::string>* names_out) {
  std::map<std::string, int> index;
  std::vector<std::string> names;
  std::vector<int> labels;
  labels.reserve(classes.size());
  for (const std::string& c : classes) {
    auto it = index.find(c);
    if (it == index.end()) {
      it = index.emplace(c, static_cast<int>(names.size())).first;
      names.push_back(c);
    }
    labels.push_back(it->second);
  }
  if (names_out) *names_out = std::move(names);
  return labels;
}

DistanceMatrixImage distance_matrix_image(const Eigen::MatrixXd& D, const std::vector<int>& labels) {
  check_input(D, labels);
  const int n = static_cast<int>(D.rows());
  const int num_classes = *std::max_element(labels.begin(), labels.end()) + 1;
  DistanceMatrixImage image;
  image.order.resize(static_cast<size_t>(n));
  std::iota(image.order.begin(), image.order.end(), 0);
  std::stable_sort(image.order.begin(), image.order.end(), [&](int a, int b) {
    return labels[static_cast<size_t>(a)] < labels[static_cast<size_t>(b)];
  });
  double largest = 0;
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j)
      if (i != j && std::isfinite(D(i, j))) largest = std::max(largest, D(i, j));
  image.values.resize(n, n);
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j)
      image.values(i, j) = D(image.order[static_cast<size_t>(i)], image.order[static_cast<size_t>(j)]) /
                           (largest > 0 ? largest : 1.0);
  for (int k = 0; k < n; ++k)
    if (k == 0 || labels[static_cast<size_t>(image.order[static_cast<size_t>(k)])] !=
                      labels[static_cast<size_t>(image.order[static_cast<size_t>(k - 1)])])
      image.class_starts.push_back(k);
  image.class_starts.push_back(n);

  image.class_mean_distance = Eigen::MatrixXd::Zero(num_classes, num_classes);
  Eigen::MatrixXd count = Eigen::MatrixXd::Zero(num_classes, num_classes);
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j)
      if (i != j) {
        image.class_mean_distance(labels[static_cast<size_t>(i)], labels[static_cast<size_t>(j)]) += D(i, j);
        count(labels[static_cast<size_t>(i)], labels[static_cast<size_t>(j)]) += 1;
      }
  for (int a = 0; a < num_classes; ++a)
    for (int b = 0; b < num_classes; ++b)
      image.class_mean_distance(a, b) = count(a, b) > 0 ? image.class_mean_distance(a, b) / count(a, b)
                                                        : std::numeric_limits<double>::quiet_NaN();
  return image;
}

}  // namespace cshapes
