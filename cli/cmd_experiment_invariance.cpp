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
       add_data_and_out_options(app, o.data, o.out, o.force, o.allow_outside, invariance_options::kData);
       add_methods_option(app, args.methods);
       add_declared(app, invariance_options::kVertices, args.vertices)->capture_default_str();
       add_declared(app, kShapesOption, args.shapes);
       add_declared(app, invariance_options::kSeeds, o.seeds)->capture_default_str();
       add_declared(app, invariance_options::kSeed, o.seed)->capture_default_str();
       add_declared(app, invariance_options::kToleranceFloor, o.tolerance_floor_percent)
           ->capture_default_str();
       add_declared(app, invariance_options::kTolerancePose, o.tolerance_pose_percent)->capture_default_str();
       add_no_draw_flag(app, args.no_draw, invariance_options::kDraw);
       add_figure_format_option(app, o.figure_format);
       app.add_flag(
           "--json", args.json,
           "print the verdicts and summary as JSON (invariance.json, with its \"failures\") instead of "
           "the verdict lines");
       add_declared_flag(app, kStrictRunOption, o.canon.strict);
       app.footer(kPartialResultHelp);
       add_canon_method_options(app);
     },
     run});

}  // namespace
}  // namespace cmd_experiment_invariance
}  // namespace cshapes::cli
