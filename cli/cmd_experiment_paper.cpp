// cshapes experiment paper --data DIR --out OUT: the paper's experiment end to end (paper_experiment.h).
// Under `mpirun -np R` the canonical forms and the ICP pairs are split over the ranks; rank 0 alone prints
// and writes the outputs.
#include <climits>
#include <cstdio>
#include <iostream>

#include "cli/command.h"
#include "cshapes/support/error.h"
#include "cshapes/support/format.h"
#include "cshapes/experiments/paper_experiment.h"
#include "cshapes/pipeline/distributed.h"

namespace cshapes::cli {
namespace cmd_experiment_paper {
namespace {

struct PaperArgs {
  PaperExperimentOptions options;
  std::string methods;  // add_methods_option: every registered method
  std::string poses = "4";
  std::string noisy = "1";
  bool no_table1 = false, no_figures = false, no_draw = false, json = false;
} args;

int run() {
  PaperExperimentOptions o = args.options;
  o.methods = methods_option(args.methods);
  o.poses_per_class = integer_or_word("--poses-per-class", args.poses, 1, INT_MAX, "all", 0);
  o.noisy_per_class = integer_or_word("--noisy-per-class", args.noisy, 0, 1000, "all",
                                      PaperExperimentOptions::kNoisyEveryPose);
  if (o.figure_vertices != 0 && o.figure_vertices < 4)
    usage_fail("--figure-vertices: expected 0 (as it is) or at least 4, got ", o.figure_vertices);
  const Communicator& comm = world_communicator();
  prepare_experiment(o.methods, o.out, o.canon);
  require_output_folder_apart(o.out, o.data);
  o.table1 = !args.no_table1;
  o.figures = !args.no_figures;
  o.draw = !args.no_draw;
  if (comm.is_root()) {  // one voice: the other ranks work silently
    o.progress = progress_printer();
    o.note = [](const std::string& line) { note(line); };
  }
  o.communicator = &comm;
  PaperExperimentSummary s = paper_experiment(o);
  if (!comm.is_root()) return 0;
  nlohmann::json j{{"out", o.out},
                   {"shapes", s.shapes},
                   {"seconds", s.seconds},
                   {"canonical_forms_computed", s.canonical_forms_computed},
                   {"canonical_forms_cached", s.canonical_forms_cached},
                   {"pairs_computed", s.pairs_computed},
                   {"pairs_cached", s.pairs_cached},
                   {"figures_drawn", s.figures_drawn},
                   {"failures", shape_failures_json(s.failures)}};
  if (args.json) {
    std::cout << j.dump(2) << std::endl;
  } else {
    std::printf(
        "experiment paper: %d shapes in %s (%ld canonical forms computed, %ld cached; %ld ICP pairs "
        "computed, %ld cached); report: %s/report.md\n",
        s.shapes, seconds_text(s.seconds).c_str(), s.canonical_forms_computed, s.canonical_forms_cached,
        s.pairs_computed, s.pairs_cached, o.out.c_str());
  }
  return exit_code_for(s.failures);
}

const bool registered = register_command(
    {{"experiment", "paper"},
     "The paper's experiment: canonical forms by every method, ICP distances, retrieval measures, the effect "
     "of topological noise, data for Figures 2-8, Table 1 and report.md (cached: reruns resume)",
     [](CLI::App& app) {
       PaperExperimentOptions& o = args.options;
       add_data_and_out_options(app, o.data, o.out, o.force, o.allow_outside, paper_experiment_options::kData);
       add_methods_option(app, args.methods);
       add_resample_option(app, o.resample.vertices);
       app.add_option("--poses-per-class", args.poses, "clean poses per class in the retrieval set, or 'all'")
           ->capture_default_str();
       app.add_option(
              "--noisy-per-class", args.noisy,
              "topologically noisy shapes per class (the data's, else glued here from another pose), or "
              "'all': the data's and a glued version of every clean pose of the class")
           ->capture_default_str();
       add_declared(app, paper_experiment_options::kGlue, o.glue)
           ->capture_default_str()
           ->check(integer_in(1, 1000));
       add_declared(app, paper_experiment_options::kSeed, o.seed)->capture_default_str();
       add_declared_flag(app, kStrictRunOption, o.canon.strict);
       add_declared(app, paper_experiment_options::kTable1Repeats, o.timing_repeats)
           ->capture_default_str()
           ->check(integer_in(1, 1000));
       add_declared_flag(app, paper_experiment_options::kTable1, args.no_table1);
       add_declared_flag(app, paper_experiment_options::kFigureData, args.no_figures);
       add_renamed(app, "--no-figures", "--no-figure-data", false,
                   "it skips the data of Figures 2-6; --no-draw only skips the drawing");
       add_renamed(app, "--no-figure", "--no-draw", false);
       add_declared_flag(app, paper_experiment_options::kDraw, args.no_draw);
       add_figure_format_option(app, o.figure_format);
       app.add_option("--figure-vertices", o.figure_vertices,
                      "Figures 3 and 5: remesh their shape to this size first (0: as it is)")
           ->capture_default_str()
           ->check(integer_in(0, 10000000));
       app.add_option("--fig5-max-iterations", o.fig5_iterations,
                      "Figure 5: maximum outer iterations per curve")
           ->capture_default_str()
           ->check(integer_in(1, 100000000));
       add_declared(app, paper_experiment_options::kCorrespondenceSamples, o.correspondence_samples)
           ->capture_default_str()
           ->check(integer_in(0, 100000000));
       app.add_flag("--json", args.json, "print the summary as JSON (with its \"failures\")");
       app.footer(kPartialResultHelp);
       add_canon_method_options(app);
     },
     run});

}  // namespace
}  // namespace cmd_experiment_paper
}  // namespace cshapes::cli
