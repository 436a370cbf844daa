// Retrieval measures of a named distance matrix as files and JSON: what `cshapes evaluate` writes and the
// Python module returns (eval/retrieval.h computes them).
//
//   metrics.json   map, nn, ft, st, e, dcg, the PR curve, per-class values, the conventions, the class blocks
//                  of matrix.csv ("class_blocks": class, first row, count)
//   pr.csv         recall, precision (interpolated, 11 points)
//   queries.csv    per query: shape, class, nn, ft, st, e, dcg, ap
//   matrix.csv     the matrix grouped by class and normalised (the paper's Fig. 7 image)
//   confusion.csv  the queries' nearest-neighbour class counts, as NN counts them: a row per class with
//                  queries (the query's class), a column per class (its nearest neighbour's); the header's
//                  first cell says so. Whole numbers unless a query's nearest are tied (shares of one)
#pragma once

#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "cshapes/eval/distance_csv.h"
#include "cshapes/eval/retrieval.h"
#include "cshapes/support/option_declaration.h"

namespace cshapes {

// `cshapes evaluate --min-class-size` and retrieval_measures(min_class_size=) (declared once,
// support/option_declaration.h); the CLI refuses a size below 1.
inline const OptionDeclaration kEvaluateMinClassSizeOption{
    "min_class_size", "--min-class-size", "classes with fewer shapes are not used as queries"};

// {map, nn, ft, st, e, dcg}.
nlohmann::json retrieval_scores_json(const RetrievalScores& scores);

// The confusion matrix as rows of numbers: a whole count as an integer, a share (tied nearest neighbours,
// eval/retrieval.h) as a double.
nlohmann::json confusion_json(const Eigen::MatrixXd& confusion);

// What metrics.json's "conventions" says: psbTable's conventions and the rule for ties.
extern const char* const kRetrievalConventions;

struct RetrievalReport {
  std::vector<std::string> class_names;  // label order
  std::vector<int> labels;
  RetrievalResult result;
  DistanceMatrixImage image;
  nlohmann::json metrics;  // the content of metrics.json
};

// Measures `input` with one class per shape (classes[i] for input.names[i]). source: what metrics.json
// names as its input.
RetrievalReport retrieval_report(const NamedDistances& input, const std::vector<std::string>& classes,
                                 const RetrievalOptions& options = {}, const std::string& source = "");

// The names of the five files above, as write_retrieval_report writes them, and of the figures `cshapes
// evaluate` draws from them (pr, confusion and matrix, as .png, .pdf and .svg): the outputs a run must not
// take as inputs.
std::vector<std::string> retrieval_report_files();

// What the figures of `cshapes evaluate` say the matrix is, in their titles: `given` as it is (its --title);
// else the recorded description (matrix_description_text) with the counts, "Coulomb, Hausdorff distance,
// tosca5k: 24 shapes, 8 classes"; else "unknown method and distance: 24 shapes, 8 classes".
std::string retrieval_figure_title(const std::string& given, const MatrixDescription& recorded,
                                   const RetrievalReport& report);

// Writes the five files above into `folder` (each atomically).
void write_retrieval_report(const std::string& folder, const NamedDistances& input,
                            const RetrievalReport& report);

}  // namespace cshapes
