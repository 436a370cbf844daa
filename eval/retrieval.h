// Shape-retrieval evaluation of a distance matrix: the precision–recall curve and the Princeton Shape
// Benchmark measures (Shilane et al. 2004), with the conventions of its psbTable program.
//
// Every shape is a query; the others (the query itself excluded) are ranked by increasing D(query, j)
// (row `query` of D). A result is relevant when it has the query's class.
// With C the size of the query's class (query included) and R = C − 1 relevant results:
//   nn   1 if the first result is relevant, else 0                          (nearest neighbour)
//   ft   relevant among the first R results, divided by R                   (first tier)
//   st   relevant among the first 2R results, divided by R                  (second tier)
//   e    E-measure over the first K = min(32, N − 1) results: with r relevant among them,
//        P = r/K, Rc = r/R and e = 2/(1/P + 1/Rc) = 2r/(K + R); 0 when r = 0
//   dcg  discounted cumulative gain G_1 + Σ_{i≥2} G_i / log2(i) (G_i = 1 if result i is relevant), divided
//        by its ideal value 1 + Σ_{i=2..R} 1/log2(i)
//   ap   average precision (1/R) Σ_{k=1..R} k / rank_k, rank_k the rank of the k-th relevant result; its
//        mean over queries is the mean average precision (map)
// Ties: results at exactly equal distances (equal doubles; inf == inf) are ties, and every measure of a
// query is its expected value over all orders of its tied results, each order equally likely (McSherry &
// Najork, "Computing information retrieval performance measures efficiently in the presence of tied scores",
// ECIR 2008): as random ranking among the tied, never by index. A group of n tied results holding r relevant
// ones puts a relevant result at each of its ranks with probability r/n, which gives nn (the share of
// relevant results among the tied nearest), ft, st, e and dcg; the k-th relevant result, the j-th of its
// group, sits at the group's i-th rank with probability C(i−1, j−1)·C(n−i, r−j)/C(n, r), which gives the
// expected precision E[k / rank_k] at recall k/R. ap is the mean of those expected precisions (= E[AP] by
// linearity), the PR curve interpolates them, and the confusion matrix counts a query's tied nearest
// neighbours as shares of one. No tolerance: distances that differ in the last bit are ranked by value, so a
// matrix without exact ties gives the measures of its one ranking.
// Reported values are micro averages (the mean over queries); per-class (macro) averages are given too.
// Queries from classes with fewer than min_class_size shapes are skipped (default 3: classes of ≤ 2
// shapes, whose tiers are a single result); their shapes still appear as (irrelevant) results of others.
//
// Precision–recall: a query's precision at its k-th relevant result is p_k = k / rank_k (its expected value
// under ties), at recall k/R.
// The curve is interpolated the usual way (TREC): precision at recall level ρ is max{p_k : k/R ≥ ρ}
// (precision at ρ = 0 is the largest p_k). The interpolated curves are averaged over queries at fixed
// recall levels (default 0, 0.05, …, 1).
//
// Cost: O(N² log N), plus O(n·r) for each group of n tied results holding r relevant ones.
#pragma once

#include <string>
#include <vector>

#include "cshapes/support/types.h"

namespace cshapes {

struct RetrievalOptions {
  int e_measure_depth = 32;  // results the E-measure looks at (psbTable: 32)
  int min_class_size = 3;    // queries from smaller classes are skipped (see above)
  // Recall levels of the averaged precision–recall curve, in [0, 1]; empty: 0, 0.05, …, 1.
  std::vector<double> recall_levels;
};

// The measures of one query, or an average of queries.
struct RetrievalScores {
  double nn = 0, ft = 0, st = 0, e = 0, dcg = 0, ap = 0;
};

struct QueryResult {
  int query = 0;  // row of D
  int label = 0;  // its class
  RetrievalScores scores;
  std::vector<int> ranking;  // the other shapes, best first; tied shapes in index order (no measure uses it)
  bool tied = false;         // whether two of the other shapes are at exactly equal distance from the query
};

struct PrecisionRecallCurve {
  std::vector<double> recall;     // the recall levels
  std::vector<double> precision;  // interpolated precision averaged over queries, one per level
};

struct RetrievalResult {
  RetrievalScores mean;                     // micro average over queries; mean.ap is the mAP
  std::vector<RetrievalScores> class_mean;  // per class label (index = label); zero for skipped classes
  std::vector<int> class_queries;           // queries per class label (0: skipped or absent)
  PrecisionRecallCurve pr;
  std::vector<QueryResult> queries;  // the evaluated queries, in row order
  int skipped = 0;                   // shapes not used as queries (class too small)
  int tied_queries = 0;              // queries whose ranking holds a tie (their measures are expectations)
  // confusion(a, b): how many queries of class a have their nearest neighbour in class b, as NN counts them:
  // a query whose n nearest are tied adds 1/n for each of them, so entries are whole numbers without ties (a
  // class below min_class_size has a zero row: its shapes are no queries).
  Eigen::MatrixXd confusion;
};

// D: N×N distances (N ≥ 2, no NaN, +inf allowed, need not be symmetric); labels: N class labels in
// [0, #classes). Throws when all shapes have one class (every result would be relevant: nothing to measure)
// and when no class is large enough to give a query.
RetrievalResult evaluate_retrieval(const Eigen::MatrixXd& D, const std::vector<int>& labels,
                                   const RetrievalOptions& options = {});

// Average precision of one query against a database: the distances to its entries and which are relevant
// (same length). Ranked by increasing distance, ties by their expected value (the rule and the code of
// evaluate_retrieval, whose ap is this function of its rows): (1/R) Σ_k k / rank_k over the R relevant
// entries. −1 when none is relevant. *nearest_relevant (when non-null): nn, the share of relevant entries
// among the nearest (1 or 0 without a tie at the top).
double average_precision(const std::vector<double>& distances, const std::vector<char>& relevant,
                         double* nearest_relevant = nullptr);

// Class labels 0, 1, … from class names, numbered in order of first appearance; names_out (when non-null)
// receives the distinct names in label order.
std::vector<int> labels_from_classes(const std::vector<std::string>& classes,
                                     std::vector<std::string>* names_out = nullptr);

// The data of the distance-matrix figure (paper Fig. 7).
struct DistanceMatrixImage {
  std::vector<int> order;         // rows of D grouped by class (stable: within a class, input order)
  Eigen::MatrixXd values;         // D reordered by `order`, divided by its largest finite off-diagonal entry
  std::vector<int> class_starts;  // first row of each class block in `order`, plus N at the end
  // class_mean_distance(a, b): mean of D over rows of class a and columns of class b (diagonal excluded).
  Eigen::MatrixXd class_mean_distance;
};
DistanceMatrixImage distance_matrix_image(const Eigen::MatrixXd& D, const std::vector<int>& labels);

}  // namespace cshapes
