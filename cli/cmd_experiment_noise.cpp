// cshapes experiment noise --data DIR --out OUT: retrieval and canonical forms against the number of glues
// (experiments/noise_experiment.h).
#include <climits>
#include <cstdio>
#include <iostream>
#include <set>

#include "cli/command.h"
#include "cshapes/support/error.h"
#include "cshapes/support/format.h"
#include "cshapes/data/topological_noise.h"
#include "cshapes/experiments/noise_experiment.h"

namespace cshapes::cli {
namespace cmd_experiment_noise {
namespace {

struct NoiseArgs {
  NoiseExperimentOptions options;
  std::string methods;  // add_methods_option: every registered method
  std::string levels = "0,1,2,4,8";
  std::string poses = "all";
  bool no_draw = false, json = false;
} args;

int run() {
  NoiseExperimentOptions o = args.options;
  o.methods = methods_option(args.methods);
  o.levels.clear();
  std::set<int> seen;
  for (const std::string& item : list_option("--levels", args.levels)) {
    int level = -1;
    size_t used = 0;
    try {
      level = std::stoi(item, &used);
    } catch (const std::exception&) {
      used = 0;
    }
    if (used != item.size() || level < 0 || level > 1000)
      usage_fail("--levels: expected glue counts from 0 to 1000, got '", item, "'");
    if (!seen.insert(level).second) usage_fail("--levels: ", level, " is given twice");
    o.levels.push_back(level);
  }
  if (o.levels.empty()) usage_fail("--levels: give at least one glue count (e.g. 0,1,2,4,8)");
  o.poses_per_class = integer_or_word("--poses-per-class", args.poses, 1, INT_MAX, "all", 0);
  prepare_experiment(o.methods, o.out, o.canon);
  require_output_folder_apart(o.out, o.data);
  o.figure = !args.no_draw;
  o.progress = progress_printer();
  o.note = [](const std::string& line) { note(line); };
  NoiseExperimentResult r = noise_experiment(o);
  if (r.chi_mismatches > 0)
    warn(std::to_string(r.chi_mismatches) +
         " glued meshes had an unexpected Euler characteristic and were "
         "left out (report.md lists them)");
  if (r.glue_failures > 0)
    warn(std::to_string(r.glue_failures) +
         " (pose, level) pairs could not be glued and were left out "
         "(report.md lists them)");
  if (args.json) {
    nlohmann::json j{{"out", o.out},
                     {"poses", r.poses},
                     {"classes", r.classes},
                     {"glued", r.glues.size()},
                     {"chi_mismatches", r.chi_mismatches},
                     {"glue_failures", r.glue_failures},
                     {"glued_computed", r.glued_computed},
                     {"glued_cached", r.glued_cached},
                     {"canonical_forms_computed", r.canonical_forms_computed},
                     {"canonical_forms_cached", r.canonical_forms_cached},
                     {"pairs_computed", r.pairs_computed},
                     {"pairs_cached", r.pairs_cached},
                     {"figure", r.figure},
                     {"seconds", r.seconds},
                     {"failures", shape_failures_json(r.failures)}};
    std::cout << j.dump(2) << std::endl;
  } else {
    std::printf(
        "experiment noise: %d poses × %zu levels in %s (%ld canonical forms computed, %ld cached; %ld "
        "ICP "
        "pairs computed, %ld cached); report: %s/report.md\n",
        r.poses, o.levels.size(), seconds_text(r.seconds).c_str(), r.canonical_forms_computed,
        r.canonical_forms_cached, r.pairs_computed, r.pairs_cached, o.out.c_str());
  }
  return exit_code_for(r.failures);
}

const bool registered = register_command(
    {{"experiment", "noise"},
     "Topological noise: every clean pose glued at 0, 1, 2, 4, 8 spots; per method and level, mAP of noisy "
     "queries among clean shapes and the noisy-vs-clean form distance (cached: reruns resume)",
     [](CLI::App& app) {
       NoiseExperimentOptions& o = args.options;
       add_data_and_out_options(app, o.data, o.out, o.force, o.allow_outside, noise_experiment_options::kData);
       add_methods_option(app, args.methods);
       add_resample_option(app, o.resample.vertices);
       add_declared(app, noise_experiment_options::kLevels, args.levels)->capture_default_str();
       app.add_option("--poses-per-class", args.poses, "clean poses per class, or 'all'")
           ->capture_default_str();
       add_declared(app, noise_experiment_options::kSeed, o.seed)->capture_default_str();
       app.add_option("--relax-steps", o.relax_steps,
                      "where a pose offers too few spots: widen the gap (×1.5) up to this many times")
           ->capture_default_str()
           ->check(within(noise_limits::kRelax));
       add_no_draw_flag(app, args.no_draw, noise_experiment_options::kDraw);
       add_figure_format_option(app, o.figure_format);
       add_declared_flag(app, kStrictRunOption, o.canon.strict);
       app.add_flag("--json", args.json, "print the summary as JSON (with its \"failures\")");
       app.footer(kPartialResultHelp);
       add_canon_method_options(app);
     },
     run});

}  // namespace
}  // namespace cmd_experiment_noise
}  // namespace cshapes::cli
