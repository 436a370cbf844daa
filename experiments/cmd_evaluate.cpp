// cshapes evaluate D.csv [--labels L.csv] -o OUT: retrieval measures of a distance matrix (eval/retrieval.h).
// Writes OUT/metrics.json (map, nn, ft, st, e, dcg, the PR curve, per-class values), OUT/pr.csv,
// OUT/queries.csv (per query), OUT/matrix.csv (the matrix grouped by class and normalised: Fig. 7's image)
// and OUT/confusion.csv (nearest-neighbour class counts).
#include <cstdio>
#include <iostream>

#include "core/atomic_file.h"
#include "eval/distance_csv.h"
#include "eval/retrieval.h"
#include "experiments/command.h"

namespace cshapes::cli {
namespace {

struct EvaluateArgs {
  std::string matrix, labels, output;
  int min_class_size = RetrievalOptions{}.min_class_size;
  int e_depth = RetrievalOptions{}.e_measure_depth;
  bool json = false;
} args;

nlohmann::json scores_json(const RetrievalScores& s) {
  return {{"map", s.ap}, {"nn", s.nn}, {"ft", s.ft}, {"st", s.st}, {"e", s.e}, {"dcg", s.dcg}};
}

int run() {
  require_output_directory(args.output);
  NamedDistances input = read_distance_csv(args.matrix);
  std::vector<std::string> classes;
  if (args.labels.empty()) {
    for (const std::string& name : input.names) classes.push_back(class_of_shape_name(name));
  } else {
    classes = read_labels_csv(args.labels, input.names);
  }
  std::vector<std::string> class_names;
  std::vector<int> labels = labels_from_classes(classes, &class_names);
  RetrievalOptions options;
  options.min_class_size = args.min_class_size;
  options.e_measure_depth = args.e_depth;
  RetrievalResult r = evaluate_retrieval(input.D, labels, options);
  DistanceMatrixImage image = distance_matrix_image(input.D, labels);

  nlohmann::json metrics = scores_json(r.mean);
  metrics["pr"] = {{"recall", r.pr.recall}, {"precision", r.pr.precision}};
  metrics["input"] = args.matrix;
  metrics["shapes"] = input.names.size();
  metrics["queries"] = r.queries.size();
  metrics["skipped"] = r.skipped;
  nlohmann::json per_class = nlohmann::json::object();
  for (size_t c = 0; c < class_names.size(); ++c) {
    nlohmann::json entry = r.class_queries[c] ? scores_json(r.class_mean[c]) : nlohmann::json::object();
    entry["queries"] = r.class_queries[c];
    per_class[class_names[c]] = entry;
  }
  metrics["classes"] = per_class;
  metrics["conventions"] =
      "psbTable: query excluded; tiers over C-1; E over the first min(32, N-1); DCG normalised by the ideal; "
      "classes with fewer than min_class_size shapes are not queries; PR interpolated (max precision at "
      "recall >= r), "
      "averaged over queries";
  metrics["min_class_size"] = options.min_class_size;

  const std::string out = args.output;
  write_file_atomically(out + "/metrics.json", [&](std::ostream& s) { s << metrics.dump(2) << '\n'; });
  std::vector<std::vector<double>> pr_rows;
  for (size_t l = 0; l < r.pr.recall.size(); ++l) pr_rows.push_back({r.pr.recall[l], r.pr.precision[l]});
  write_csv(out + "/pr.csv", {"recall", "precision"}, pr_rows);
  write_file_atomically(out + "/queries.csv", [&](std::ostream& s) {
    s << "shape,class,nn,ft,st,e,dcg,ap\n";
    s.precision(10);
    for (const QueryResult& q : r.queries)
      s << input.names[static_cast<size_t>(q.query)] << ',' << class_names[static_cast<size_t>(q.label)]
        << ',' << q.scores.nn << ',' << q.scores.ft << ',' << q.scores.st << ',' << q.scores.e << ','
        << q.scores.dcg << ',' << q.scores.ap << '\n';
  });
  std::vector<std::string> ordered_names;
  for (int k : image.order) ordered_names.push_back(input.names[static_cast<size_t>(k)]);
  write_distance_csv(out + "/matrix.csv", ordered_names, image.values);
  write_file_atomically(out + "/confusion.csv", [&](std::ostream& s) {
    s << "class";
    for (const std::string& c : class_names) s << ',' << c;
    s << '\n';
    for (size_t a = 0; a < class_names.size(); ++a) {
      s << class_names[a];
      for (size_t b = 0; b < class_names.size(); ++b)
        s << ',' << image.confusion(static_cast<Index>(a), static_cast<Index>(b));
      s << '\n';
    }
  });

  if (args.json) {
    std::cout << metrics.dump(2) << std::endl;
  } else {
    std::printf("%zu shapes, %zu classes, %zu queries (%d skipped)\n", input.names.size(), class_names.size(),
                r.queries.size(), r.skipped);
    std::printf("  mAP %.4f   NN %.4f   FT %.4f   ST %.4f   E %.4f   DCG %.4f\n", r.mean.ap, r.mean.nn,
                r.mean.ft, r.mean.st, r.mean.e, r.mean.dcg);
  }
  note("wrote " + out + "/metrics.json, pr.csv, queries.csv, matrix.csv, confusion.csv");
  return 0;
}

const bool registered = register_command(
    {{"evaluate"},
     "Retrieval measures of a distance matrix: mAP, nearest neighbour, tiers, E-measure, DCG, PR curve",
     [](CLI::App& app) {
       app.add_option("MATRIX", args.matrix,
                      "distance matrix CSV (header row of shape names, or plain numbers)")
           ->required();
       app.add_option(
           "--labels", args.labels,
           "classes: 'name,class' lines or one class per line (default: from the names, cat0 -> cat)");
       app.add_option("-o,--output", args.output, "output directory")->required();
       app.add_option("--min-class-size", args.min_class_size,
                      "classes with fewer shapes are not used as queries")
           ->check(integer_at_least(1));
       app.add_option("--e-depth", args.e_depth, "results the E-measure looks at")
           ->check(integer_at_least(1));
       app.add_flag("--json", args.json, "print metrics.json to stdout");
     },
     run});

}  // namespace
}  // namespace cshapes::cli
