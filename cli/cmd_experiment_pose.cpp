// cshapes experiment pose --data DIR --out OUT: pose invariance of each method's canonical forms against
// ground-truth correspondences, and their metric faithfulness (experiments/pose_invariance.h).
#include <iostream>

#include "cli/command.h"
#include "cshapes/experiments/pose_invariance.h"

namespace cshapes::cli {
namespace cmd_experiment_pose {
namespace {

struct PoseArgs {
  PoseInvarianceOptions options;
  std::string methods;  // add_methods_option: every registered method
  std::string shapes;
  bool no_draw = false, no_parts = false, json = false;
} args;

int run() {
  PoseInvarianceOptions o = args.options;
  o.methods = methods_option(args.methods);
  o.shapes = list_option("--shapes", args.shapes);
  o.figure = !args.no_draw;
  o.parts = !args.no_parts;
  prepare_experiment(o.methods, o.out, o.canon);
  require_output_folder_apart(o.out, o.data);
  o.note = [](const std::string& line) { note(line); };
  const PoseInvarianceResult r = pose_experiment(o);
  if (!r.figure_problem.empty() && !args.no_draw) warn("no figure: " + r.figure_problem);
  if (args.json)
    std::cout << pose_invariance_json(r).dump(2) << std::endl;
  else
    std::cout << pose_invariance_markdown(r, o);
  return exit_code_for(r.failures);
}

const bool registered = register_command(
    {{"experiment", "pose"},
     "Pose invariance of the canonical forms against ground-truth correspondences (TOSCA corres/*.vts, "
     "TOPKIDS *_ref.txt, or poses sharing their faces as `generate dataset` writes them), and their edge "
     "stretch and geodesic stress (cached: reruns resume)",
     [](CLI::App& app) {
       PoseInvarianceOptions& o = args.options;
       add_data_and_out_options(app, o.data, o.out, o.force, o.allow_outside, pose_experiment_options::kData);
       add_methods_option(app, args.methods);
       add_resample_option(app, o.resample.vertices);
       add_declared(app, kShapesOption, args.shapes);
       add_declared(app, pose_experiment_options::kSamples, o.samples)
           ->capture_default_str()
           ->check(integer_in(0, 100000000));
       app.add_option("--stress-sources", o.stress_sources,
                      "fast-marching sources per shape for the geodesic stress (0: skip)")
           ->capture_default_str()
           ->check(integer_in(0, 100000));
       app.add_option("--label", o.label, "name of this configuration in the CSV rows and the table");
       app.add_option(
              "--part-persistence", o.part_finder.min_persistence,
              "parts: an extremity is a maximum of the geodesic distance from the centre persisting over "
              "at least this fraction of the largest distance")
           ->capture_default_str()
           ->check(number_in(0.001, 1.0));
       app.add_option(
              "--part-fraction", o.part_finder.part_fraction,
              "parts: a vertex is in its nearest extremity's part when nearer than this fraction of the "
              "extremity's distance to the centre")
           ->capture_default_str()
           ->check(number_in(0.001, 1.0));
       add_declared_flag(app, pose_experiment_options::kParts, args.no_parts);
       add_no_draw_flag(app, args.no_draw, pose_experiment_options::kDraw);
       add_figure_format_option(app, o.figure_format);
       app.add_flag("--json", args.json,
                    "print the summary as JSON (with its \"failures\") instead of pose.md");
       add_declared_flag(app, kStrictRunOption, o.canon.strict);
       app.footer(kPartialResultHelp);
       add_canon_method_options(app);
     },
     run});

}  // namespace
}  // namespace cmd_experiment_pose
}  // namespace cshapes::cli
