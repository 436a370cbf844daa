// cshapes evaluate D.csv [--labels L.csv] -o OUT: retrieval measures of a distance matrix (ties: expected
// values over the orders of the tied results, eval/retrieval.h), written by
// eval/retrieval_report.h (OUT/metrics.json, pr.csv, queries.csv, matrix.csv, confusion.csv), and their
// figures pr.png, confusion.png and matrix.png (.pdf or .svg by --figure-format;
// experiments/plots/evaluate_figures.py) when Python with matplotlib is found, each titled with what the
// matrix is: --title, else the method, distance and data distmat recorded in the labels file.
#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <iostream>

#include "cshapes/eval/distance_csv.h"
#include "cshapes/eval/retrieval_report.h"
#include "cshapes/support/output_folder.h"
#include "cli/command.h"
#include "cshapes/experiments/figures.h"

namespace cshapes::cli {
namespace cmd_evaluate {
namespace {

struct EvaluateArgs {
  std::string matrix, labels, output, title;
  FigureFormat figure_format = FigureFormat::png;
  int min_class_size = RetrievalOptions{}.min_class_size;
  int e_depth = RetrievalOptions{}.e_measure_depth;
  bool json = false, no_draw = false, force = false;
} args;

int run() {
  require_output_directory(args.output);
  // Without --labels, the labels file distmat wrote beside the matrix (D.labels.csv), when there is one.
  const std::string beside = labels_path_for(args.matrix);
  const std::string labels = !args.labels.empty()                       ? args.labels
                             : std::filesystem::is_regular_file(beside) ? beside
                                                                        : "";
  require_outputs_not_inputs(args.output, retrieval_report_files(), {args.matrix, labels}, "--out");
  // The previous run's files move aside until this one is complete (a failure brings them back).
  OutputRun output(args.output, "evaluate", {}, args.force);
  const NamedDistances input = read_distance_csv(args.matrix);
  for (const std::string& line : check_distance_matrix(input, args.matrix)) warn(line);
  std::vector<std::string> classes;
  if (labels.empty()) {
    for (const std::string& name : input.names) classes.push_back(class_of_shape_name(name));
  } else {
    classes = read_labels_csv(labels, input.names);
    if (args.labels.empty()) note("classes from " + labels);
  }
  // One class: every result relevant, every measure 1. Refused here with where the classes came from (the
  // library refuses it too, in its own words).
  if (std::all_of(classes.begin(), classes.end(), [&](const std::string& c) { return c == classes[0]; }))
    fail(args.matrix, ": all ", classes.size(), " shapes have class '", classes[0], "' (",
         labels.empty() ? std::string("from their names: cat0 -> cat") : "from " + labels,
         "), so there is no retrieval to measure: give each shape its class with --labels FILE ('name,class' "
         "lines; distmat writes ",
         beside, ")");
  RetrievalOptions options;
  options.min_class_size = args.min_class_size;
  options.e_measure_depth = args.e_depth;
  RetrievalReport report = retrieval_report(input, classes, options, args.matrix);
  report.metrics["classes_from"] = labels.empty() ? "names" : labels;
  // What the figures say the matrix is: --title, else what distmat recorded beside the classes.
  const MatrixDescription recorded = labels.empty() ? MatrixDescription{} : read_matrix_description(labels);
  report.metrics["description"] = {
      {"method", recorded.method}, {"distance", recorded.distance}, {"data", recorded.data}};
  report.metrics["title"] = retrieval_figure_title(args.title, recorded, report);
  write_retrieval_report(args.output, input, report);
  const RetrievalResult& r = report.result;
  if (args.json) {
    std::cout << report.metrics.dump(2) << std::endl;
  } else {
    std::printf("%zu shapes, %zu classes, %zu queries", input.names.size(), report.class_names.size(),
                r.queries.size());
    if (r.skipped > 0)  // the one reason a shape is not a query
      std::printf(" (%d skipped: their class has fewer than %d shapes; --min-class-size)", r.skipped,
                  std::max(args.min_class_size, 2));
    std::printf("\n");
    // Retrieval measures in [0, 1] with the field's three decimals (0.926); metrics.json has every digit.
    std::printf("  mAP %.3f   NN %.3f   FT %.3f   ST %.3f   E %.3f   DCG %.3f\n", r.mean.ap, r.mean.nn,
                r.mean.ft, r.mean.st, r.mean.e, r.mean.dcg);
    if (r.tied_queries > 0)
      std::printf(
          "  %d queries have tied distances: their measures are expected values over the orders of "
          "the tied results\n",
          r.tied_queries);
  }
  note("wrote " + args.output + "/metrics.json, pr.csv, queries.csv, matrix.csv, confusion.csv");
  if (!args.no_draw) {
    const FigureFormat format = args.figure_format;
    const FigureRun figures = draw_figure("evaluate_figures.py", {args.output}, args.output + "/pr", format);
    if (figures.drawn)
      note("wrote " + args.output + "/" + figure_file_name("pr", format) + ", " +
           figure_file_name("confusion", format) + ", " + figure_file_name("matrix", format));
    else
      warn("no figures: " + figures.problem);
  }
  output.commit();
  return 0;
}

const bool registered = register_command(
    {{"evaluate"},
     "Retrieval measures of a distance matrix: mAP, nearest neighbour, tiers, E-measure, DCG, PR curve",
     [](CLI::App& app) {
       app.add_option("MATRIX", args.matrix,
                      std::string("distance matrix CSV (header row of shape names, or plain numbers); ") +
                          kDistanceMatrixRules)
           ->required();
       app.add_option("--labels", args.labels,
                      "classes: 'name,class' lines or one class per line (default: the matrix's labels file "
                      "that distmat writes, D.labels.csv beside D.csv, else from the names, cat0 -> cat); "
                      "a name given two classes is refused, and so is one class for all shapes");
       add_out_folder_option(app, args.output, "output folder, created when missing")->required();
       add_declared(app, kEvaluateMinClassSizeOption, args.min_class_size)->check(integer_at_least(1));
       app.add_option("--e-depth", args.e_depth, "results the E-measure looks at")
           ->check(integer_at_least(1));
       app.add_flag("--json", args.json, "print metrics.json to stdout");
       add_no_draw_flag(app, args.no_draw, kEvaluateDrawOption);
       add_figure_format_option(app, args.figure_format);
       app.add_option(
           "--title", args.title,
           "what the matrix is, in every figure's title (e.g. 'Coulomb, Hausdorff distance, TOSCA'); "
           "default: the method, distance and data that distmat recorded in the labels file, else "
           "'unknown method and distance'");
       add_force_flag(app, args.force);
     },
     run});

}  // namespace
}  // namespace cmd_evaluate
}  // namespace cshapes::cli
