// cshapes compare RUN1 RUN2 … --out DIR: the per-method tables and PR curves of several `experiment
// retrieval` runs on the same data (checked by their inputs' checksums) in one report and one figure
// (experiments/compare_runs.h).
#include <cstdio>
#include <iostream>

#include "cli/command.h"
#include "cshapes/experiments/compare_runs.h"
#include "cshapes/experiments/retrieval_experiment.h"

namespace cshapes::cli {
namespace cmd_compare {
namespace {

struct CompareArgs {
  CompareRunsOptions options;
  bool no_draw = false, json = false;
} args;

int run() {
  CompareRunsOptions o = args.options;
  require_output_directory(o.out);
  o.figures = !args.no_draw;
  o.note = [](const std::string& line) { note(line); };
  const CompareRunsResult r = compare_runs(o);
  if (args.json) {
    nlohmann::json methods = nlohmann::json::array();
    for (const ComparedMethod& m : r.methods) {
      nlohmann::json per = nlohmann::json::object();
      for (const auto& [kind, scores] : m.scores) per[kind] = retrieval_scores_json(scores);
      methods.push_back(
          {{"method", m.method}, {"run", r.runs[m.run].folder}, {"shapes", m.shapes}, {"distances", per}});
    }
    std::cout << nlohmann::json{{"out", o.out},
                                {"experiment", r.experiment},
                                {"inputs_digest", r.inputs_digest},
                                {"shapes", r.shapes},
                                {"methods", methods},
                                {"figures", r.figures}}
                     .dump(2)
              << std::endl;
  } else {
    std::printf("compare: %zu runs of experiment %s on the same %d shapes; report: %s/report.md\n",
                r.runs.size(), r.experiment.c_str(), r.shapes, o.out.c_str());
    for (const ComparedMethod& m : r.methods) {
      auto it = m.scores.find("hausdorff");
      if (it == m.scores.end()) continue;
      const RetrievalScores& s = it->second;
      std::printf("  %-14s mAP %.3f  NN %.3f  FT %.3f  ST %.3f  (Hausdorff)  %s\n", m.title.c_str(), s.ap,
                  s.nn, s.ft, s.st, r.runs[m.run].folder.c_str());
    }
  }
  return kExitOk;
}

const bool registered = register_command(
    {{"compare"},
     "The tables and PR curves of several `experiment retrieval` runs on the same data (checked by the "
     "inputs' checksums) side by side: one report.md, compare.json and pr.png, nothing recomputed",
     [](CLI::App& app) {
       CompareRunsOptions& o = args.options;
       app.add_option(
              "RUNS", o.runs,
              "output folders of complete `cshapes experiment retrieval` runs, two or more, on the same "
              "data (their retrieval.json's inputs' digest) with the same protocol; a method in two runs "
              "must have the same results in both (other experiments' outputs are refused)")
           ->required();
       add_out_folder_option(app, o.out, option_help(kCompareOutOption, OptionSkin::Cli))->required();
       add_force_flag(app, o.force);
       add_no_draw_flag(app, args.no_draw, kCompareDrawOption);
       add_figure_format_option(app, o.figure_format);
       add_renamed(app, "--pdf", "--figure-format pdf", false, "one option for the format of every figure");
       app.add_flag("--json", args.json, "print the summary as JSON");
     },
     run});

}  // namespace
}  // namespace cmd_compare
}  // namespace cshapes::cli
