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

// Natural logarithms of k! for k = 0..n (std::lgamma, accurate to a few ulps at every k: no running sum).
std::vector<double> log_factorials(int n) {
  std::vector<double> log_factorial(static_cast<size_t>(n) + 1);
  for (int k = 0; k <= n; ++k) log_factorial[static_cast<size_t>(k)] = std::lgamma(k + 1.0);
  return log_factorial;
}

// A run of results at one distance in a query's ranking: ranks first_rank + 1 … first_rank + size.
struct TieGroup {
  int first_rank = 0;  // results ranked before the group
  int size = 0;
  int relevant = 0;  // relevant results among them
};

// The tie groups of a ranking: distances in rank order (increasing), equal only when exactly equal (inf ==
// inf), and which results are relevant.
std::vector<TieGroup> tie_groups(const std::vector<double>& ranked_distances,
                                 const std::vector<char>& ranked_relevant) {
  std::vector<TieGroup> groups;
  for (size_t k = 0; k < ranked_distances.size(); ++k) {
    if (k == 0 || ranked_distances[k] != ranked_distances[k - 1])
      groups.push_back({static_cast<int>(k), 0, 0});
    ++groups.back().size;
    groups.back().relevant += ranked_relevant[k] ? 1 : 0;
  }
  return groups;
}

// The expected precision E[k / rank_k] at each relevant result k = 1..R, in rank order, appended to
// `precisions`. Alone in its group, the k-th relevant result is at rank first_rank + 1: k / rank_k as without
// ties, to the bit. Else, the j-th relevant of a group of n holding r is at the group's i-th rank with
// probability C(i−1, j−1)·C(n−i, r−j)/C(n, r) (McSherry & Najork 2008), i = j … n − r + j.
void append_expected_precisions(const TieGroup& g, int relevant_before,
                                const std::vector<double>& log_factorial, std::vector<double>& precisions) {
  if (g.size == 1) {
    precisions.push_back(static_cast<double>(relevant_before + 1) / (g.first_rank + 1));
    return;
  }
  auto log_binomial = [&](int a, int b) {
    return log_factorial[static_cast<size_t>(a)] - log_factorial[static_cast<size_t>(b)] -
           log_factorial[static_cast<size_t>(a - b)];
  };
  const int n = g.size, r = g.relevant;
  const double log_orders = log_binomial(n, r);
  for (int j = 1; j <= r; ++j) {
    double expected_inverse_rank = 0;
    for (int i = j; i <= n - r + j; ++i)
      expected_inverse_rank +=
          std::exp(log_binomial(i - 1, j - 1) + log_binomial(n - i, r - j) - log_orders) / (g.first_rank + i);
    precisions.push_back((relevant_before + j) * expected_inverse_rank);
  }
}

// Expected relevant results among the first `depth` ranks: each rank of a group of n holding r is relevant
// with probability r/n.
double expected_relevant_within(const std::vector<TieGroup>& groups, int depth) {
  double count = 0;
  for (const TieGroup& g : groups) {
    if (g.first_rank >= depth) break;
    if (g.relevant == 0) continue;
    const int ranks_within = std::min(g.size, depth - g.first_rank);
    count += static_cast<double>(g.relevant) * ranks_within / g.size;
  }
  return count;
}

// Average precision from the precisions at the ranks of the relevant results, in rank order (every relevant
// result found, so their count is R): one summation order for every caller, so results agree to the bit.
double mean_of_precisions(const std::vector<double>& precision_at_relevant) {
  return std::accumulate(precision_at_relevant.begin(), precision_at_relevant.end(), 0.0) /
         static_cast<double>(precision_at_relevant.size());
}

// Every measure of one query from its ranking in tie groups (R = relevant_total ≥ 1 relevant results, the
// E-measure over the first `depth`), each the expected value over the orders of tied results (see the
// header); precision_at_relevant receives E[p_k], k = 1..R. One code path for evaluate_retrieval and
// average_precision.
RetrievalScores score_query(const std::vector<TieGroup>& groups, int relevant_total, int depth,
                            const std::vector<double>& log_factorial,
                            std::vector<double>& precision_at_relevant) {
  RetrievalScores s;
  const double R = relevant_total;
  s.nn = static_cast<double>(groups.front().relevant) / groups.front().size;
  s.ft = expected_relevant_within(groups, relevant_total) / R;
  s.st = expected_relevant_within(groups, 2 * relevant_total) / R;
  const double e = expected_relevant_within(groups, depth);
  s.e = e > 0 ? 2 * e / (depth + R) : 0.0;  // 2/(1/P + 1/R) with P = r/K, R = r/(C−1)
  double dcg = 0;
  int relevant_before = 0;
  precision_at_relevant.clear();
  for (const TieGroup& g : groups) {
    if (g.relevant == 0) continue;
    double gains = 0;  // the gains of the group's ranks, each relevant with probability r/n
    for (int rank = g.first_rank + 1; rank <= g.first_rank + g.size; ++rank)
      gains += rank == 1 ? 1.0 : 1.0 / std::log2(static_cast<double>(rank));
    dcg += g.relevant * gains / g.size;
    append_expected_precisions(g, relevant_before, log_factorial, precision_at_relevant);
    relevant_before += g.relevant;
  }
  double ideal = 1;
  for (int i = 2; i <= relevant_total; ++i) ideal += 1.0 / std::log2(static_cast<double>(i));
  s.dcg = dcg / ideal;
  s.ap = mean_of_precisions(precision_at_relevant);
  return s;
}

}  // namespace

RetrievalResult evaluate_retrieval(const Eigen::MatrixXd& D, const std::vector<int>& labels,
                                   const RetrievalOptions& options) {
  check_input(D, labels);
  CSHAPES_REQUIRE(options.e_measure_depth >= 1, "retrieval: e_measure_depth must be >= 1");
  const int n = static_cast<int>(D.rows());
  CSHAPES_REQUIRE(std::any_of(labels.begin(), labels.end(), [&](int label) { return label != labels[0]; }),
                  "retrieval: all ", n,
                  " shapes have one class, so every result is relevant and every measure would be 1: there "
                  "is no retrieval to measure (each shape needs its class)");
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
  result.confusion = Eigen::MatrixXd::Zero(num_classes, num_classes);

  const int depth = std::min(options.e_measure_depth, n - 1);
  const std::vector<double> log_factorial = log_factorials(n);
  std::vector<double> ranked_distances(static_cast<size_t>(n - 1));
  std::vector<char> ranked_relevant(static_cast<size_t>(n - 1));
  std::vector<double> precision_at_relevant;  // E[p_k] = E[k / rank_k]
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
    for (size_t k = 0; k < query.ranking.size(); ++k) {
      ranked_distances[k] = D(q, query.ranking[k]);
      ranked_relevant[k] = labels[static_cast<size_t>(query.ranking[k])] == label;
    }
    const std::vector<TieGroup> groups = tie_groups(ranked_distances, ranked_relevant);
    query.tied = static_cast<int>(groups.size()) < n - 1;
    result.tied_queries += query.tied ? 1 : 0;
    query.scores = score_query(groups, relevant_total, depth, log_factorial, precision_at_relevant);
    const RetrievalScores& s = query.scores;

    // Interpolated precision at each recall level: the best (expected) precision at recall ≥ the level.
    const double R = relevant_total;
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
    // The nearest neighbour's class, as NN counts it: each of n tied nearest a share 1/n, added per class.
    const int nearest = groups.front().size;
    std::map<int, int> nearest_of_class;
    for (int k = 0; k < nearest; ++k) ++nearest_of_class[labels[static_cast<size_t>(query.ranking[k])]];
    for (const auto& [nearest_label, count] : nearest_of_class)
      result.confusion(label, nearest_label) += static_cast<double>(count) / nearest;
    result.queries.push_back(std::move(query));
  }
  // A query needs another shape of its class, so a class of one shape is never a query, whatever the minimum.
  const int needed = std::max(options.min_class_size, 2);
  CSHAPES_REQUIRE(
      !result.queries.empty(), "retrieval: no class has ", needed,
      " shapes or more, so there is no query to evaluate",
      options.min_class_size < 2 ? " (a query needs another shape of its own class)"
      : options.min_class_size > 2
          ? " (the Princeton benchmark leaves classes of fewer as queries out; a minimum class size of "
            "2, `--min-class-size 2` or min_class_size=2, takes classes of two)"
          : "");

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
                         double* nearest_relevant) {
  CSHAPES_REQUIRE(distances.size() == relevant.size(), "average_precision: ", distances.size(),
                  " distances but ", relevant.size(), " relevance flags");
  for (size_t k = 0; k < distances.size(); ++k)
    CSHAPES_REQUIRE(!std::isnan(distances[k]), "average_precision: distance ", k, " is NaN");
  std::vector<int> order(distances.size());
  std::iota(order.begin(), order.end(), 0);
  std::stable_sort(order.begin(), order.end(), [&](int a, int b) { return distances[a] < distances[b]; });
  std::vector<double> ranked_distances;
  std::vector<char> ranked_relevant;
  for (int k : order) {
    ranked_distances.push_back(distances[static_cast<size_t>(k)]);
    ranked_relevant.push_back(relevant[static_cast<size_t>(k)]);
  }
  const int relevant_total =
      static_cast<int>(std::count_if(relevant.begin(), relevant.end(), [](char r) { return r != 0; }));
  if (nearest_relevant) *nearest_relevant = 0;
  if (relevant_total == 0) return -1.0;
  const std::vector<TieGroup> groups = tie_groups(ranked_distances, ranked_relevant);
  std::vector<double> precision_at_relevant;
  const RetrievalScores s =
      score_query(groups, relevant_total, static_cast<int>(distances.size()),
                  log_factorials(static_cast<int>(distances.size())), precision_at_relevant);
  if (nearest_relevant) *nearest_relevant = s.nn;
  return s.ap;
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
