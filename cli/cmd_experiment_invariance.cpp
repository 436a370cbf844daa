// cshapes experiment invariance --data DIR --out OUT: how much each method's canonical form changes under
// transformations of its input that must not change it (renumbering, face order, rigid motion, scale,
// jitter), and under remeshing, beside its pose variation; a verdict per method
// (experiments/invariance_experiment.h).
#include <cstdio>
#include <iostream>
#include <set>

#include "cli/command.h"
#include "cshapes/experiments/invariance_experiment.h"
#include "cshapes/support/format.h"

namespace cshapes::cli {
namespace cmd_experiment_invariance {
namespace {

struct InvarianceArgs {
  InvarianceOptions options;
  std::string methods;  // add_methods_option: every registered method
  std::string shapes;
  std::string vertices = "0";
  bool no_draw = false, json = false;
} args;

// --vertices: comma-separated resolutions, each 0 (as given) or a vertex count.
std::vector<Index> resolutions(const std::string& text) {
  using invariance_limits::kSmallestResolution;
  std::vector<Index> out;
  std::set<Index> seen;
  for (const std::string& item : list_option("--vertices", text)) {
    long long n = -1;
    size_t used = 0;
    try {
      n = std::stoll(item, &used);
    } catch (const std::exception&) {
      used = 0;
    }
    if (used != item.size() ||
        !(n == 0 || (n >= kSmallestResolution && invariance_limits::kVertices.holds(n))))
      usage_fail("--vertices: expected 0 (the shapes as given) or a vertex count from ", kSmallestResolution,
                 " to ", format_limit_number(invariance_limits::kVertices.maximum), ", got '", item, "'");
    if (!seen.insert(n).second) usage_fail("--vertices: ", n, " is given twice");
    out.push_back(static_cast<Index>(n));
  }
  if (out.empty()) usage_fail("--vertices: give at least one resolution (0: the shapes as given)");
  return out;
}

int run() {
  InvarianceOptions o = args.options;
  o.methods = methods_option(args.methods);
  o.shapes = list_option("--shapes", args.shapes);
  o.vertices = resolutions(args.vertices);
  o.figure = !args.no_draw;
  prepare_experiment(o.methods, o.out, o.canon);
  require_output_folder_apart(o.out, o.data);
  o.progress = progress_printer();
  o.note = [](const std::string& line) { note(line); };
  const InvarianceResult r = invariance_experiment(o);
  if (!r.figure_problem.empty() && !args.no_draw) warn("no figure: " + r.figure_problem);
  if (args.json) {
    std::cout << invariance_json(r, o).dump(2) << std::endl;
  } else {
    std::printf("experiment invariance: %zu shapes, %zu resolution%s, %s; report: %s/invariance.md\n",
                r.shapes.size(), r.resolutions.size(), r.resolutions.size() == 1 ? "" : "s",
                seconds_text(r.seconds).c_str(), o.out.c_str());
    for (const InvarianceVerdict& v : r.verdicts)
      if (v.resolution < 0)
        std::printf("  %-14s %-12s %s\n", canonical_form_method_title(v.method).c_str(), v.verdict.c_str(),
                    v.reason.c_str());
  }
  return exit_code_for(r.failures);
}

const bool registered = register_command(
    {{"experiment", "invariance"},
     "How much each canonical form changes under transformations that must not change it (vertex "
     "renumbering, face order, rigid motion, scale 1e-6 and 1e3, jitter 1e-9) and under remeshing at ±20%, "
     "beside its pose variation; a verdict per method, invariance.md and a figure (cached: reruns resume)",
     [](CLI::App& app) {
       InvarianceOptions& o = args.options;
       add_data_and_out_options(
           app, o.data, o.out, o.force, o.allow_outside,
           "folder of meshes (class = name without trailing digits), manifest.csv or a .cla "
           "file; two clean poses of a class give a pose pair");
       add_methods_option(app, args.methods);
       app.add_option("--vertices", args.vertices,
                      "comma-separated resolutions: each shape remeshed to about N vertices first (cached; "
                      "OUT/resampled/N), 0 the shapes as given")
           ->capture_default_str();
       app.add_option("--shapes", args.shapes, "only these shapes (comma-separated names); default: all");
       app.add_option("--seeds", o.seeds, "vertex renumberings per shape and resolution")
           ->capture_default_str()
           ->check(within(invariance_limits::kSeeds));
       app.add_option("--seed", o.seed,
                      "the first renumbering's seed (the next ones count up), and the face order's, rigid "
                      "motion's and jitter's")
           ->capture_default_str()
           ->check(within(invariance_limits::kSeed));
       app.add_option(
              "--tolerance-floor", o.tolerance_floor_percent,
              "verdict: an RMSE up to this % of the diagonal passes (or up to --tolerance-pose, the larger)")
           ->capture_default_str()
           ->check(within(invariance_limits::kToleranceFloor));
       app.add_option("--tolerance-pose", o.tolerance_pose_percent,
                      "verdict: an RMSE up to this % of the method's median pose variation passes")
           ->capture_default_str()
           ->check(within(invariance_limits::kTolerancePose));
       add_no_draw_flag(app, args.no_draw, "invariance.png");
       add_figure_format_option(app, o.figure_format);
       app.add_flag(
           "--json", args.json,
           "print the verdicts and summary as JSON (invariance.json, with its \"failures\") instead of "
           "the verdict lines");
       app.add_flag(
           "--strict", o.canon.strict,
           "stop at the first shape that fails (exit code 1) instead of leaving it out (exit code 3), "
           "with no geodesic fallback; and refuse a mesh a method would have to repair");
       app.footer(kPartialResultHelp);
       add_canon_method_options(app);
     },
     run});

}  // namespace
}  // namespace cmd_experiment_invariance
}  // namespace cshapes::cli
