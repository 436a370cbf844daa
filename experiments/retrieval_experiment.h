// `cshapes experiment retrieval`: a whole collection as a retrieval benchmark, every shape a query against all
// the others (leave-one-out), by every canonical-form method and under each distance between forms.
//
// Per method: the canonical forms and the ICP distances between all pairs (pipeline/dataset_distances.h:
// what `cshapes distmat` computes, cached in out/cache, split over the ranks of an MPI run), then under each
// of the three distances after ICP (hausdorff: the paper's, chamfer, rmse; matching/shape_distance.h) the
// Princeton measures overall and per class (NN, FT, ST, E, DCG, mAP: eval/retrieval.h), the averaged
// precision–recall curve and the nearest-neighbour confusion matrix. The collection is a folder, a
// manifest.csv or a Princeton .cla file (data/dataset.h); with resample.vertices > 0 every shape is remeshed
// to that size first (pipeline/resampled_dataset.h, the remesh's Hausdorff distance and angles in the
// report).
//
// Files under out/ (each written atomically; a killed run resumes from out/cache):
//   classes.cla                      the collection's classes in its order (PSB format, data/classification.h)
//   resampled/                       with resampling: the remeshed shapes, manifest.csv, resample.csv
//   METHOD/classes.cla               the shapes of METHOD's matrices, in their order (fewer when one failed)
//   METHOD/DISTANCE.csv              the matrix with shape names (`cshapes evaluate` reads it)
//   METHOD/DISTANCE.txt, .matrix     the same for the evaluation tools: SHREC's plain text, the PSB's binary
//                                    (eval/distance_csv.h), rows in METHOD/classes.cla's order
//   METHOD/DISTANCE/                 metrics.json, pr.csv, queries.csv, matrix.csv, confusion.csv
//                                    (eval/retrieval_report.h)
//   retrieval.json                   every measure of the run, for the figures and other tools; with the
//                                    inputs' checksums (each shape's SHA-256 and their digest,
//                                    data/dataset_checksums.h) and the protocol's settings, by which
//                                    `cshapes compare` (experiments/compare_runs.h) tells runs on the
//                                    same data
//   figures/pr.png, per_class.png, confusion.png   (experiments/plots/retrieval_figures.py; matplotlib;
//                                                  .pdf or .svg by options.figure_format)
//   report.md                        write_retrieval_report
//
// A shape whose form fails by a method is left out of that method's matrices (named in the failures, the
// report and retrieval.json), unless canon.strict. Distributed (options.communicator with R > 1 ranks): every
// rank computes its share of the forms and pairs through out/cache (which every rank must see); rank 0
// writes every file; the other ranks' results hold only the counts.
#pragma once

#include <map>
#include <string>
#include <vector>

#include "cshapes/support/communicator.h"
#include "cshapes/data/dataset_checksums.h"
#include "cshapes/eval/retrieval_report.h"
#include "cshapes/pipeline/canonical_form_methods.h"
#include "cshapes/pipeline/resampled_dataset.h"
#include "cshapes/pipeline/shape_failures.h"
#include "cshapes/support/figure_format.h"
#include "cshapes/support/stage_time.h"

namespace cshapes {

// The experiment's own options, each declared once (support/option_declaration.h): `cshapes experiment
// retrieval`'s flags and experiment_retrieval()'s keywords.
namespace retrieval_experiment_options {
inline const OptionDeclaration kEDepth{"e_depth", "--e-depth",
                                       "results the E-measure looks at (psbTable: 32)"};
inline const OptionDeclaration kMinClassSize{
    "min_class_size", "--min-class-size",
    "classes with fewer shapes give no queries (their shapes are still results)"};
inline const OptionDeclaration kData{"data", "--data",
    "folder of meshes (class = name without trailing digits), manifest.csv, or a Princeton .cla file (model ID: "
    "ID.off or mID.off … in the .cla's folder)"};
inline const OptionDeclaration kDraw =
    negated_option("draw", "--no-draw", "draw the figures (drawing needs Python with matplotlib)");
inline const OptionDeclaration kTwoStageReference{
    "two_stage_reference", "--two-stage-reference",
    "two-stage: the folder an exact run (K = 0) of the same collection and methods wrote, read, never "
    "written; each method's recall@K and its exact measures are reported beside the two-stage ones"};
inline const std::vector<const OptionDeclaration*> kAll = {&kEDepth, &kMinClassSize, &kDraw,
                                                           &kTwoStageReference};
}  // namespace retrieval_experiment_options

struct RetrievalExperimentOptions {
  std::string data;  // folder of meshes, manifest.csv or FILE.cla
  std::string out;   // output folder
  // Write into `out` although it holds files cshapes did not write (support/output_folder.h); they stay.
  bool force = false;
  // Read manifest or .cla entries outside the dataset's folder (data/dataset.h: read_dataset).
  bool allow_outside = false;
  std::vector<std::string> methods = canonical_form_methods();  // every registered method
  // Method options: the experiments' (heat geodesics for MDS), as `cshapes distmat` and the other experiments.
  CanonicalFormOptions canon = experiment_canonical_form_options();
  ResampleOptions resample;  // vertices > 0: every shape remeshed to about that many vertices first
  // Two-stage mode (pipeline/dataset_distances.h; 0: every pair aligned, the exact run): ICP on each shape's
  // two_stage_k descriptor-nearest candidates only. two_stage_reference: an exact run's output folder (its
  // METHOD/hausdorff.csv and measures), for recall@K and the exact measures beside the two-stage ones.
  int two_stage_k = 0;
  std::string two_stage_reference;
  RetrievalOptions retrieval;  // the measures' conventions (eval/retrieval.h: psbTable's)
  bool figures = true;         // draw the figures (when matplotlib is found)
  // The figures' format: png, pdf or svg (support/figure_format.h).
  FigureFormat figure_format = FigureFormat::png;
  ProgressFn progress;
  NoteFn note;
  const Communicator* communicator = nullptr;  // the ranks sharing the work; nullptr: this process
};

// The distances between canonical forms after ICP, in the order of the report: the paper's first.
const std::vector<std::string>& retrieval_distances();

struct RetrievalMethodResult {
  std::string method;
  std::vector<std::string> names, classes;              // the shapes of its matrices, in order
  std::map<std::string, RetrievalReport> by_distance;  // per retrieval_distances() entry
  long forms_computed = 0, forms_cached = 0, pairs_computed = 0, pairs_cached = 0;
  double seconds = 0;
  // Per form, as computed (cached forms keep their time): the median seconds, and the largest peak memory in
  // bytes of a method run as a program of its own (−1: not measured, an in-process method).
  double form_seconds_median = 0, form_peak_bytes_max = -1;
  // Two-stage mode: the pairs aligned (of N(N−1)/2); with a reference, recall@K under the Hausdorff distance
  // (pipeline/dataset_distances.h) and the exact run's measures under each distance (its METHOD/ files).
  long pairs_aligned = 0;
  double recall = -1;
  std::map<std::string, RetrievalScores> exact;
};

struct RetrievalExperimentResult {
  RetrievalExperimentOptions options;  // what was run (its callbacks unused by the report)
  std::string data;                    // what was read: options.data, or the resampled manifest
  int shapes = 0;                      // in the collection
  std::vector<std::string> class_names;  // the collection's classes, in order
  std::vector<int> class_sizes;          // shapes per class
  // The collection's files as given (before any resampling), by content (rank 0): what `cshapes compare`
  // checks runs against.
  DatasetChecksums inputs;
  bool resampled = false;
  ResampledDataset resampling;  // when resampled
  std::vector<RetrievalMethodResult> methods;
  std::vector<ShapeFailure> failures;  // every method's (pipeline/shape_failures.h)
  std::vector<std::string> figures;    // drawn, relative to out
  std::string figures_note;            // why not, when not drawn
  double seconds = 0;
  // Where the time went, in order (support/stage_time.h): "resample"; per method "forms", "pairs" and
  // "measures" (the matrices' files and the measures under each distance); "figures" when drawn. `cores`: the
  // machine's (what cpu / wall is out of).
  std::vector<StageTime> profile;
  int cores = 0;
};

// The measurement and its data files (everything above but report.md). On ranks other than 0 of a distributed
// run only the counts are filled.
RetrievalExperimentResult run_retrieval_experiment(const RetrievalExperimentOptions& options);

// Draws the figures from the data files in folder (experiments/plots/retrieval_figures.py), in
// result.options.figure_format; records what was drawn, or why not, in result.
void draw_retrieval_figures(RetrievalExperimentResult& result, const std::string& folder);

// report.md in folder from the result alone: the overall table (method × distance), the per-class table of
// each method, the confusion matrices, the resampling table, the failures, the files.
void write_retrieval_report(const RetrievalExperimentResult& result, const std::string& folder);

// The pieces of report.md's tables that other reports of retrieval runs share (`cshapes compare`): a
// distance's title ("Hausdorff (the paper's)"), the header of the six measures (" | NN | FT | ST | E | DCG |
// mAP |") with its alignment row, and a row's cells of them (three decimals).
std::string retrieval_distance_title(const std::string& distance);
extern const char* const kRetrievalMeasuresHeader;
extern const char* const kRetrievalMeasuresRule;
std::string retrieval_measures_cells(const RetrievalScores& scores);

// The experiment as `cshapes experiment retrieval` (and cshapes.experiment_retrieval) runs it:
// run_retrieval_experiment, then the figures and report.md on rank 0.
RetrievalExperimentResult retrieval_experiment(const RetrievalExperimentOptions& options);

}  // namespace cshapes
