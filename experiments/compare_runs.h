// `cshapes compare RUN1 RUN2 … --out DIR`: the results of several runs of one experiment on the same data
// side by side, so that a group can add its method to a published run without recomputing the others.
//
// Supported: `cshapes experiment retrieval` (experiments/retrieval_experiment.h). Each RUN must be the output
// folder of a complete run of it (its .cshapes-outputs record, support/output_folder.h) whose retrieval.json
// records its inputs' checksums (data/dataset_checksums.h; runs written before cshapes recorded them are
// refused with a request to rerun, which the run's cache makes cheap). Refused, each with an Error naming the
// folder or file and what was expected, before anything is written:
//   - a missing folder, a folder that is no cshapes output, an incomplete run, a folder given twice;
//   - another command's outputs (experiment paper, noise, pose, topkids: not supported yet, said);
//   - runs on different data (the inputs' digests differ: the first shape that differs is named) or under a
//     different protocol (E-measure depth, smallest query class, resampling);
//   - one method in two runs with different results (named, with the first measure that differs); with the
//     same results it is one row, from the first run, the others named beside it.
//
// Files under DIR (an OutputRun: a rerun replaces them whole; a failure leaves the previous set):
//   report.md     one table, method × distance, the retrieval report's six measures, each row's run folder;
//                 the methods from outside with their doors, as their runs' outside-methods.json name them
//   compare.json  the same with each method's PR curves and per-class measures, the runs and the inputs'
//   digest pr.png        the PR curves of every method, one panel per distance
//   (experiments/plots/compare_figure.py,
//                 retrieval_figures.py's drawing; pr.pdf or pr.svg by `figure_format`); methods.json
//                 beside it
#pragma once

#include <map>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "cshapes/eval/retrieval.h"
#include "cshapes/support/progress.h"
#include "cshapes/support/figure_format.h"
#include "cshapes/support/option_declaration.h"

namespace cshapes {

// `cshapes compare --out` and compare_runs(out=) (declared once, support/option_declaration.h).
inline const OptionDeclaration kCompareOutOption{
    "out", "--out",
    "output folder, created when missing (report.md, compare.json, the PR figure); not one of the runs' folders"};
inline const OptionDeclaration kCompareDrawOption =
    negated_option("draw", "--no-draw", "draw the PR figure, pr.png (drawing needs Python with matplotlib)");

struct CompareRunsOptions {
  std::vector<std::string>
      runs;         // output folders of complete `cshapes experiment retrieval` runs, two or more
  std::string out;  // output folder; may not be one of the runs, nor inside one, nor hold one
  // Write into `out` although it holds files cshapes did not write (support/output_folder.h); they stay.
  bool force = false;
  bool figures = true;  // draw the PR figure (when matplotlib is found)
  // Its format: pr.png, pr.pdf or pr.svg (support/figure_format.h).
  FigureFormat figure_format = FigureFormat::png;
  NoteFn note;          // one line per run read
};

struct ComparedRun {
  std::string folder;                // as given
  std::string data;                  // the collection the run was given (its --data), as it recorded it
  nlohmann::json build;              // the build that ran it (retrieval.json's "build")
  std::vector<std::string> methods;  // its methods, in its order
};

struct ComparedMethod {
  std::string method, title;    // the run's name and title of the method
  size_t run = 0;               // index into CompareRunsResult::runs: the first run holding it (its numbers)
  std::vector<size_t> also_in;  // later runs holding the same method with the same results
  int shapes = 0;  // shapes of its matrices: fewer than the collection when its run left some out
  // A method from outside (pipeline/outside_methods.h): its door ("command", "forms", "function") and the
  // command, folder or function its run's outside-methods.json names; both empty for a built-in method.
  std::string door, door_text;
  std::map<std::string, RetrievalScores> scores;  // per distance: the six measures, micro averages
  std::map<std::string, nlohmann::json> entries;  // per distance: the run's whole entry (PR curve, per class)
};

struct CompareRunsResult {
  std::string experiment;              // "retrieval"
  std::string inputs_digest;           // the runs' common digest of their inputs (data/dataset_checksums.h)
  int shapes = 0;                      // in the collection
  std::vector<std::string> classes;    // the collection's classes, in the first run's order
  nlohmann::json protocol;             // the runs' common settings (retrieval.json's "protocol")
  std::vector<std::string> distances;  // every distance of any run, the first run's order first
  std::vector<ComparedRun> runs;
  std::vector<ComparedMethod> methods;  // in order of first appearance over the runs
  std::vector<std::string> figures;     // drawn, relative to the output folder
  std::string figures_note;             // why not, when not drawn
};

// Reads and checks the runs (everything refused above throws); writes nothing.
CompareRunsResult read_compared_runs(const std::vector<std::string>& runs);

// compare.json in folder (what the figure script reads; written atomically).
void write_compare_json(const CompareRunsResult& result, const std::string& folder);
// pr.png (pr.pdf, pr.svg: `format`) in folder from its compare.json; records what was drawn, or why not, in
// result.
void draw_compare_figure(CompareRunsResult& result, const std::string& folder,
                         FigureFormat format = FigureFormat::png);
// report.md in folder from the result alone.
void write_compare_report(const CompareRunsResult& result, const std::string& folder);

// The comparison as `cshapes compare` (and cshapes.compare_runs) runs it: the output folder claimed
// (OutputRun), the runs read and checked, compare.json, the figure, report.md, then the folder committed.
CompareRunsResult compare_runs(const CompareRunsOptions& options);

}  // namespace cshapes
