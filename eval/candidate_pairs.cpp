#include "cshapes/eval/candidate_pairs.h"

#include <algorithm>
#include <cmath>
#include <set>

#include "cshapes/support/error.h"

namespace cshapes {

namespace {

// The k columns j ≠ i of row i with the smallest values, nearest first (ties: lower index).
std::vector<int> nearest_in_row(const Eigen::MatrixXd& distances, int i, int k) {
  const int n = static_cast<int>(distances.cols());
  std::vector<int> others;
  for (int j = 0; j < n; ++j)
    if (j != i) others.push_back(j);
  const int take = std::min(k, static_cast<int>(others.size()));
  auto nearer = [&](int a, int b) {
    return distances(i, a) < distances(i, b) || (distances(i, a) == distances(i, b) && a < b);
  };
  std::partial_sort(others.begin(), others.begin() + take, others.end(), nearer);
  others.resize(static_cast<size_t>(take));
  return others;
}

}  // namespace

std::vector<std::vector<int>> nearest_candidates(const Eigen::MatrixXd& distances, int k) {
  const int n = static_cast<int>(distances.rows());
  CSHAPES_REQUIRE(distances.cols() == n, "candidates: a ", distances.rows(), "×", distances.cols(),
                  " matrix");
  CSHAPES_REQUIRE(k >= 1, "candidates: k = ", k, ", expected at least 1");
  std::vector<std::vector<int>> result(static_cast<size_t>(n));
  for (int i = 0; i < n; ++i) result[static_cast<size_t>(i)] = nearest_in_row(distances, i, k);
  return result;
}

std::vector<std::pair<int, int>> candidate_pairs(const std::vector<std::vector<int>>& candidates) {
  std::set<std::pair<int, int>> pairs;
  for (size_t i = 0; i < candidates.size(); ++i)
    for (int c : candidates[i]) {
      const int a = static_cast<int>(i);
      CSHAPES_REQUIRE(c != a && c >= 0 && c < static_cast<int>(candidates.size()), "candidate pairs: shape ",
                      a, " has candidate ", c);
      pairs.insert({std::min(a, c), std::max(a, c)});
    }
  return {pairs.begin(), pairs.end()};
}

void rank_unmeasured_last(Eigen::MatrixXd& D, const Eigen::MatrixXd& descriptor_distances) {
  const Index n = D.rows();
  CSHAPES_REQUIRE(D.cols() == n && descriptor_distances.rows() == n && descriptor_distances.cols() == n,
                  "rank_unmeasured_last: matrices of different sizes");
  double largest = -1;
  for (Index i = 0; i < n; ++i)
    for (Index j = 0; j < n; ++j)
      if (i != j && std::isfinite(D(i, j))) largest = std::max(largest, D(i, j));
  CSHAPES_REQUIRE(largest >= 0, "rank_unmeasured_last: no pair was measured");
  for (Index i = 0; i < n; ++i)
    for (Index j = 0; j < n; ++j)
      if (i != j && std::isnan(D(i, j))) D(i, j) = largest * (1 + descriptor_distances(i, j));
}

double candidate_recall(const Eigen::MatrixXd& reference, const std::vector<std::vector<int>>& candidates) {
  const int n = static_cast<int>(reference.rows());
  CSHAPES_REQUIRE(reference.cols() == n && static_cast<int>(candidates.size()) == n,
                  "candidate recall: ", candidates.size(), " candidate lists for a ", reference.rows(), "×",
                  reference.cols(), " reference");
  double total = 0;
  for (int i = 0; i < n; ++i) {
    const std::vector<int>& mine = candidates[static_cast<size_t>(i)];
    if (mine.empty()) continue;
    const int k = static_cast<int>(mine.size());
    const std::vector<int> truth = nearest_in_row(reference, i, k);
    const std::set<int> truth_set(truth.begin(), truth.end());
    int hits = 0;
    for (int c : mine) hits += truth_set.count(c) ? 1 : 0;
    total += static_cast<double>(hits) / k;
  }
  return n > 0 ? total / n : 1.0;
}

}  // namespace cshapes
