// cshapes experiment retrieval --data DIR|manifest.csv|FILE.cla --out OUT: a whole collection as a retrieval
// benchmark, every shape a query, every method, three distances (experiments/retrieval_experiment.h). Under
// `mpirun -np R` the forms and pairs are split over the ranks; rank 0 alone prints and writes the outputs.
#include <cstdio>
#include <iostream>

#include "cli/command.h"
#include "cshapes/support/format.h"
#include "cshapes/experiments/retrieval_experiment.h"
#include "cshapes/pipeline/dataset_distances.h"
#include "cshapes/pipeline/distributed.h"

namespace cshapes::cli {
namespace cmd_experiment_retrieval {
namespace {

struct RetrievalArgs {
  RetrievalExperimentOptions options;
  std::string methods;  // add_methods_option: every registered method
  bool no_draw = false, json = false;
} args;

int run() {
  RetrievalExperimentOptions o = args.options;
  o.methods = methods_option(args.methods);
  const Communicator& comm = world_communicator();
  prepare_experiment(o.methods, o.out, o.canon);
  require_output_folder_apart(o.out, o.data);
  o.figures = !args.no_draw;
  if (comm.is_root()) {  // one voice: the other ranks work silently
    o.progress = progress_printer();
    o.note = [](const std::string& line) { note(line); };
  }
  o.communicator = &comm;
  const RetrievalExperimentResult r = retrieval_experiment(o);
  if (!comm.is_root()) return 0;
  nlohmann::json methods = nlohmann::json::object();
  for (const RetrievalMethodResult& m : r.methods) {
    nlohmann::json per = nlohmann::json::object();
    for (const auto& [kind, report] : m.by_distance) per[kind] = retrieval_scores_json(report.result.mean);
    if (o.two_stage_k > 0) {
      per["two_stage"] = {{"k", o.two_stage_k}, {"pairs_aligned", m.pairs_aligned}};
      if (m.recall >= 0) per["two_stage"]["recall_at_k"] = m.recall;
      for (const auto& [kind, scores] : m.exact) per["two_stage"]["exact"][kind] = retrieval_scores_json(scores);
    }
    methods[m.method] = per;
  }
  if (args.json) {
    std::cout << nlohmann::json{{"out", o.out},
                                {"shapes", r.shapes},
                                {"classes", r.class_names.size()},
                                {"seconds", r.seconds},
                                {"resampled", r.resampled},
                                {"methods", methods},
                                {"figures", r.figures},
                                {"failures", shape_failures_json(r.failures)}}
                     .dump(2)
              << std::endl;
  } else {
    std::printf("experiment retrieval: %d shapes in %zu classes, %s; report: %s/report.md\n", r.shapes,
                r.class_names.size(), seconds_text(r.seconds).c_str(), o.out.c_str());
    for (const RetrievalMethodResult& m : r.methods) {
      const RetrievalScores& s = m.by_distance.at("hausdorff").result.mean;
      std::printf("  %-14s mAP %.3f  NN %.3f  FT %.3f  ST %.3f  (Hausdorff)",
                  canonical_form_method_title(m.method).c_str(), s.ap, s.nn, s.ft, s.st);
      if (o.two_stage_k > 0) std::printf("  two-stage: %ld pairs aligned", m.pairs_aligned);
      if (m.recall >= 0) std::printf(", recall@%d %.3f", o.two_stage_k, m.recall);
      const auto exact = m.exact.find("hausdorff");
      if (exact != m.exact.end()) std::printf(", exact mAP %.3f", exact->second.ap);
      std::printf("\n");
    }
  }
  return exit_code_for(r.failures);
}

const bool registered = register_command(
    {{"experiment", "retrieval"},
     "A whole collection as a retrieval benchmark: every shape a query against all others, every method, "
     "the three distances; measures overall and per class, PR curves, confusion, figures, report.md "
     "(cached: reruns resume)",
     [](CLI::App& app) {
       RetrievalExperimentOptions& o = args.options;
       add_data_and_out_options(app, o.data, o.out, o.force, o.allow_outside, retrieval_experiment_options::kData);
       add_methods_option(app, args.methods);
       add_resample_option(app, o.resample.vertices);
       add_declared_flag(app, kStrictRunOption, o.canon.strict);
       add_declared(app, retrieval_experiment_options::kEDepth, o.retrieval.e_measure_depth)
           ->capture_default_str()
           ->check(integer_in(1, 1000000));
       add_declared(app, retrieval_experiment_options::kMinClassSize, o.retrieval.min_class_size)
           ->capture_default_str()
           ->check(integer_in(2, 1000000));
       add_declared(app, kTwoStageKOption, o.two_stage_k)->capture_default_str()->check(integer_at_least(0));
       add_declared(app, retrieval_experiment_options::kTwoStageReference, o.two_stage_reference);
       add_no_draw_flag(app, args.no_draw, retrieval_experiment_options::kDraw);
       add_figure_format_option(app, o.figure_format);
       app.add_flag("--json", args.json, "print the summary as JSON (with its \"failures\")");
       app.footer(kPartialResultHelp);
       add_canon_method_options(app);
     },
     run});

}  // namespace
}  // namespace cmd_experiment_retrieval
}  // namespace cshapes::cli
