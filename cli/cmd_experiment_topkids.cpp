// cshapes experiment topkids --data DIR --out OUT: point maps between poses with real topological noise
// (SHREC'16 TOPKIDS), per canonization method and for the inputs, scored against ground truth
// (experiments/topkids_experiment.h). The figure is drawn by experiments/plots/topkids_figure.py.
#include <cstdio>
#include <filesystem>
#include <iostream>

#include "cli/command.h"
#include "cshapes/support/error.h"
#include "cshapes/support/format.h"
#include "cshapes/experiments/topkids_experiment.h"

namespace cshapes::cli {
namespace cmd_experiment_topkids {
namespace {

struct TopkidsArgs {
  TopkidsExperimentOptions options;
  std::string methods;  // add_methods_option: every registered method
  std::string poses;    // empty: all
  std::string scoring_geodesics = "fmm";
  bool no_draw = false, json = false;
} args;

int run() {
  TopkidsExperimentOptions o = args.options;
  o.methods = methods_option(args.methods);
  o.poses = list_option("--poses", args.poses);
  try {
    check_distinct(o.poses, "--poses");
  } catch (const Error& e) {
    throw UsageError(e.what());
  }
  try {
    o.scoring_geodesics.method = parse_geodesic_method(args.scoring_geodesics);
  } catch (const Error& e) {
    usage_fail("--scoring-geodesics: ", e.what());
  }
  prepare_experiment(o.methods, o.out, o.canon);
  require_output_folder_apart(o.out, o.data);
  o.figure = !args.no_draw;
  o.progress = progress_printer();
  o.note = [](const std::string& line) { note(line); };
  TopkidsExperimentResult r = topkids_experiment(o);
  if (!r.figure_problem.empty() && !args.no_draw) warn("no figure: " + r.figure_problem);
  if (args.json) {
    nlohmann::json j{{"out", o.out},
                     {"poses", r.poses.size()},
                     {"seconds", r.seconds},
                     {"canonical_forms_computed", r.forms_computed},
                     {"canonical_forms_cached", r.forms_cached},
                     {"scorings_computed", r.scorings_computed},
                     {"scorings_cached", r.scorings_cached},
                     {"figure", r.figure},
                     {"failures", shape_failures_json(r.failures)}};
    for (const TopkidsSummary& s : r.summaries)
      j["summary"][s.method] = {
          {"mean_error", s.mean_error}, {"under_0.1", s.under_0_1}, {"under_0.25", s.under_0_25}};
    std::cout << j.dump(2) << std::endl;
    return exit_code_for(r.failures);
  }
  std::printf("experiment topkids: %zu poses in %s (%ld canonical forms computed, %ld cached)\n",
              r.poses.size(), seconds_text(r.seconds).c_str(), r.forms_computed, r.forms_cached);
  // The error's unit said once; the mean to three significant figures, the shares (in [0, 1]) to three
  // decimals as the benchmark's tables have them. The JSON (--json) and topkids.csv keep every digit.
  std::printf(
      "errors in units of √area of the reference; shares of the samples with error <= 0.1 and "
      "<= 0.25\n");
  std::printf("%-10s %10s %8s %8s\n", "method", "mean error", "<= 0.1", "<= 0.25");
  for (const TopkidsSummary& s : r.summaries)
    std::printf("%-10s %10.3g %8.3f %8.3f\n", s.method.c_str(), s.mean_error, s.under_0_1, s.under_0_25);
  std::printf("report: %s/report.md\n", o.out.c_str());
  return exit_code_for(r.failures);
}

const bool registered = register_command(
    {{"experiment", "topkids"},
     "Point maps under real topological noise (SHREC'16 TOPKIDS): each pose's canonical form aligned by ICP "
     "to "
     "the reference's, errors by the benchmark's protocol, per method and for the inputs; curves, table, "
     "report.md (cached: reruns resume)",
     [](CLI::App& app) {
       TopkidsExperimentOptions& o = args.options;
       add_data_and_out_options(app, o.data, o.out, o.force, o.allow_outside, topkids_options::kData);
       add_declared(app, topkids_options::kReference, o.reference)->capture_default_str();
       add_declared(app, topkids_options::kPoses, args.poses);
       add_methods_option(app, args.methods);
       add_resample_option(app, o.resample.vertices);
       add_declared(app, topkids_options::kSamples, o.samples)
           ->capture_default_str()
           ->check(integer_in(0, 100000000));
       app.add_option("--scoring-geodesics", args.scoring_geodesics,
                      "geodesics on the reference for the errors: fmm, graph, heat, heat-cgal, exact")
           ->capture_default_str();
       app.add_option("--max-error", o.max_threshold, "largest error of the curves (units of sqrt(area))")
           ->capture_default_str()
           ->check(number_above(0.25));
       app.add_flag("--icp-axis-swaps", o.icp.try_axis_swaps,
                    "ICP also starts from the principal-axis poses with two axes exchanged (12 more starts; "
                    "default off, as in the retrieval)");
       add_declared_flag(app, kStrictRunOption, o.canon.strict);
       add_no_draw_flag(app, args.no_draw, topkids_options::kDraw);
       add_figure_format_option(app, o.figure_format);
       app.add_flag("--json", args.json, "print the summary as JSON (with its \"failures\")");
       app.footer(kPartialResultHelp);
       add_canon_method_options(app);
     },
     run});

}  // namespace
}  // namespace cmd_experiment_topkids
}  // namespace cshapes::cli
