#include "cshapes/eval/retrieval_report.h"

#include <cmath>

#include "cshapes/support/atomic_file.h"
#include "cshapes/support/figure_format.h"

namespace cshapes {

nlohmann::json retrieval_scores_json(const RetrievalScores& s) {
  return {{"map", s.ap}, {"nn", s.nn}, {"ft", s.ft}, {"st", s.st}, {"e", s.e}, {"dcg", s.dcg}};
}

nlohmann::json confusion_json(const Eigen::MatrixXd& confusion) {
  nlohmann::json rows = nlohmann::json::array();
  for (Index a = 0; a < confusion.rows(); ++a) {
    nlohmann::json row = nlohmann::json::array();
    for (Index b = 0; b < confusion.cols(); ++b) {
      const double count = confusion(a, b);
      if (count == std::floor(count) && std::abs(count) < 1e15)
        row.push_back(static_cast<long long>(count));
      else
        row.push_back(count);
    }
    rows.push_back(row);
  }
  return rows;
}

const char* const kRetrievalConventions =
    "psbTable: query excluded; tiers over C-1; E over the first min(32, N-1); DCG normalised by the ideal; "
    "classes with fewer than min_class_size shapes are not queries; PR interpolated (max precision at "
    "recall >= r), averaged over queries; ties (exactly equal distances): every measure, the PR curve and "
    "the "
    "confusion counts are expected values over all orders of the tied results (McSherry & Najork, ECIR "
    "2008), "
    "never an order by index";

RetrievalReport retrieval_report(const NamedDistances& input, const std::vector<std::string>& classes,
                                 const RetrievalOptions& options, const std::string& source) {
  RetrievalReport report;
  report.labels = labels_from_classes(classes, &report.class_names);
  report.result = evaluate_retrieval(input.D, report.labels, options);
  report.image = distance_matrix_image(input.D, report.labels);
  report.metrics = retrieval_scores_json(report.result.mean);
  const RetrievalResult& r = report.result;
  nlohmann::json& metrics = report.metrics;
  metrics["pr"] = {{"recall", r.pr.recall}, {"precision", r.pr.precision}};
  metrics["input"] = source;
  metrics["shapes"] = input.names.size();
  metrics["queries"] = r.queries.size();
  metrics["skipped"] = r.skipped;
  metrics["tied_queries"] = r.tied_queries;
  nlohmann::json per_class = nlohmann::json::object();
  for (size_t c = 0; c < report.class_names.size(); ++c) {
    nlohmann::json entry =
        r.class_queries[c] ? retrieval_scores_json(r.class_mean[c]) : nlohmann::json::object();
    entry["queries"] = r.class_queries[c];
    per_class[report.class_names[c]] = entry;
  }
  metrics["classes"] = per_class;
  metrics["conventions"] = kRetrievalConventions;
  metrics["min_class_size"] = options.min_class_size;
  // matrix.csv's rows class by class: the figure labels and outlines each block.
  nlohmann::json blocks = nlohmann::json::array();
  const DistanceMatrixImage& image = report.image;
  for (size_t b = 0; b + 1 < image.class_starts.size(); ++b) {
    const int first = image.class_starts[b], end = image.class_starts[b + 1];
    if (end <= first) continue;
    const int label = report.labels[static_cast<size_t>(image.order[static_cast<size_t>(first)])];
    blocks.push_back({{"class", report.class_names[static_cast<size_t>(label)]},
                      {"first", first},
                      {"count", end - first}});
  }
  metrics["class_blocks"] = blocks;

  return report;
}

std::vector<std::string> retrieval_report_files() {
  std::vector<std::string> files = {"metrics.json", "pr.csv", "queries.csv", "matrix.csv", "confusion.csv"};
  for (const std::string& format : figure_format_names())
    for (const char* figure : {"pr", "confusion", "matrix"})
      files.push_back(std::string(figure) + "." + format);
  return files;
}

std::string retrieval_figure_title(const std::string& given, const MatrixDescription& recorded,
                                   const RetrievalReport& report) {
  if (!given.empty()) return given;
  const std::string described = matrix_description_text(recorded);
  return (described.empty() ? std::string("unknown method and distance") : described) + ": " +
         std::to_string(report.labels.size()) + " shapes, " + std::to_string(report.class_names.size()) +
         " classes";
}

void write_retrieval_report(const std::string& folder, const NamedDistances& input,
                            const RetrievalReport& report) {
  const RetrievalResult& r = report.result;
  write_file_atomically(folder + "/metrics.json",
                        [&](std::ostream& s) { s << report.metrics.dump(2) << '\n'; });
  std::vector<std::vector<double>> pr_rows;
  for (size_t l = 0; l < r.pr.recall.size(); ++l) pr_rows.push_back({r.pr.recall[l], r.pr.precision[l]});
  write_csv(folder + "/pr.csv", {"recall", "precision"}, pr_rows);
  write_file_atomically(folder + "/queries.csv", [&](std::ostream& s) {
    s << "shape,class,nn,ft,st,e,dcg,ap\n";
    s.precision(10);
    for (const QueryResult& q : r.queries)
      s << input.names[static_cast<size_t>(q.query)] << ','
        << report.class_names[static_cast<size_t>(q.label)] << ',' << q.scores.nn << ',' << q.scores.ft << ','
        << q.scores.st << ',' << q.scores.e << ',' << q.scores.dcg << ',' << q.scores.ap << '\n';
  });
  std::vector<std::string> ordered_names;
  for (int k : report.image.order) ordered_names.push_back(input.names[static_cast<size_t>(k)]);
  write_distance_csv(folder + "/matrix.csv", ordered_names, report.image.values);
  // A row per class with queries (a class below min_class_size has none), a column per class (any shape
  // may be a nearest neighbour).
  const Index num_classes = static_cast<Index>(report.class_names.size());
  const Eigen::MatrixXd& confusion = r.confusion;
  write_file_atomically(folder + "/confusion.csv", [&](std::ostream& s) {
    s.precision(10);  // whole counts print as such; shares of tied nearest neighbours with 10 digits
    // Says what its rows and columns are: the query's class down, its nearest neighbour's class across.
    s << "query class / nearest neighbour class";
    for (const std::string& c : report.class_names) s << ',' << c;
    s << '\n';
    for (Index a = 0; a < num_classes; ++a) {
      if (r.class_queries[static_cast<size_t>(a)] == 0) continue;
      s << report.class_names[static_cast<size_t>(a)];
      for (Index b = 0; b < num_classes; ++b) s << ',' << confusion(a, b);
      s << '\n';
    }
  });
}

}  // namespace cshapes
