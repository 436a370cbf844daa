// `cshapes experiment paper`: the paper's experiment end to end (§3), and more.
//
// Per class: N near-isometric poses + K topologically noisy shapes (the dataset's own, or made here by gluing
// another pose with data/topological_noise.h); canonical forms by every method (pipeline/canonical_forms.h,
// cached); ICP distances between all pairs (eval/pairwise_distances.h, cached); retrieval measures and PR
// curves (eval/retrieval.h); the effect of topological noise on each method's canonical form; point-map
// errors where ground-truth correspondences exist; the data behind Figures 2-8; Table 1
// (experiments/timing_table.h); report.md. Imperfect meshes are read as they are and repaired per method,
// said per shape in notes and report.md; a file no method can use (unreadable, too few vertices) is skipped
// with its reason. Everything is written under options.out; every expensive intermediate is cached in
// out/cache, so a run that is killed resumes where it stopped. A shape whose canonical form fails by any
// method is left out by every method, named with its reason in summary.failures, report.md and metrics.json
// (unless canon.strict: then the error ends the run); the run goes on with the others.
//
// Distributed (options.communicator with R > 1 ranks, pipeline/distributed.h): the two expensive stages are
// split over the ranks — canonical forms by expected cost (vertex counts, longest first), the ICP pairs of
// each method in blocks of equal count — through the cache in out/cache, which every rank must see. Rank 0
// does everything else and writes every output; the other ranks write nothing but cache entries and return
// after the pairs (their summary holds only the counts). The outputs are those of one process, byte for byte.
#pragma once

#include <functional>
#include <map>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "cshapes/data/dataset.h"
#include "cshapes/support/communicator.h"
#include "cshapes/experiments/timing_table.h"
#include "cshapes/pipeline/canonical_form_methods.h"
#include "cshapes/pipeline/resampled_dataset.h"
#include "cshapes/pipeline/shape_failures.h"
#include "cshapes/support/figure_format.h"

namespace cshapes {

// The experiment's own options, each declared once (support/option_declaration.h): `cshapes experiment
// paper`'s flags and experiment_paper()'s keywords.
namespace paper_experiment_options {
inline const OptionDeclaration kGlue{"glue", "--glue", "glues per noisy shape made here"};
inline const OptionDeclaration kSeed{"seed", "--seed", "seed of the noise placement"};
inline const OptionDeclaration kTable1Repeats{"table1_repeats", "--table1-repeats",
                                              "Table 1: timed runs per median"};
inline const OptionDeclaration kCorrespondenceSamples{
    "correspondence_samples", "--correspondence-samples",
    "ground-truth samples per pair for the point-map error (0: skip)"};
inline const OptionDeclaration& kData = kDataOption;
inline const OptionDeclaration kTable1 = negated_option(
    "table1", "--no-table1",
    "measure Table 1 (the seconds of pre-computation and of one iteration at 561, 3,505 and 22,738 "
    "vertices), which checks the report's two claims on cost; the run's longest part: it remeshes a biped to "
    "22,738 vertices and computes its all-pairs geodesic matrix (2.1 GB of memory; about 1-2 minutes on two "
    "cores, with progress)");
inline const OptionDeclaration kFigureData =
    negated_option("figure_data", "--no-figure-data", "compute the data of Figures 2, 3, 4, 5 and 6");
inline const OptionDeclaration kDraw = negated_option(
    "draw", "--no-draw", "draw the figures from their data (drawing needs Python with matplotlib)");
inline const std::vector<const OptionDeclaration*> kAll = {
    &kTable1, &kFigureData, &kDraw, &kGlue, &kSeed, &kTable1Repeats, &kCorrespondenceSamples};
}  // namespace paper_experiment_options

struct PaperExperimentOptions {
  std::string data;                                             // folder of meshes or manifest.csv
  std::string out;                                              // output folder
  // Write into `out` although it holds files cshapes did not write (support/output_folder.h); they stay.
  bool force = false;
  // Read manifest or .cla entries outside the dataset's folder (data/dataset.h: read_dataset).
  bool allow_outside = false;
  // vertices > 0: every shape remeshed to about that many vertices first (pipeline/resampled_dataset.h,
  // into out/resampled; the report's "Resampling" section). Ground-truth correspondences (corres/) do not
  // survive a remesh: no point-map errors then.
  ResampleOptions resample;
  std::vector<std::string> methods = canonical_form_methods();  // every registered method
  int poses_per_class = 4;  // clean poses per class in the retrieval set (the paper's 4); ≤ 0: all
  // Topologically noisy shapes per class (the paper's 1): the data's noisy shapes first, then shapes glued
  // here from the poses not in the retrieval set, then from the retrieval poses. kNoisyEveryPose: every noisy
  // shape of the data and a glued version of every clean pose of the class (retrieval poses and spare ones
  // alike), each a query of its own.
  int noisy_per_class = 1;
  static constexpr int kNoisyEveryPose = -1;
  int glue = 2;            // glues per noisy shape made here
  std::uint64_t seed = 1;  // noise placement
  // Method options (geodesics for MDS: canon.geodesics, heat by default).
  CanonicalFormOptions canon = experiment_canonical_form_options();
  bool table1 = true;      // measure Table 1 (remeshes to 3,505 and 22,738 vertices)
  int timing_repeats = 5;  // Table 1: runs per median
  bool figures = true;     // compute the data of Figures 2, 3, 4, 5
  // Draw every figure (beside report.md: experiments/plots/paper_figures.py, through experiments/figures.h)
  // when a Python with matplotlib is found; report.md says when they could not be drawn, and how to.
  bool draw = true;
  // The figures' format: png, pdf or svg (support/figure_format.h).
  FigureFormat figure_format = FigureFormat::png;
  // Figures 3 and 5: remesh their shape to this many vertices first; 0: the data's own resolution (tosca5k:
  // 5,000 vertices, about 23 s for both figures' 13,000 outer iterations).
  int figure_vertices = 0;
  std::vector<int> fig3_iterations = {300, 600, 900, 3000, 10000};
  int fig5_iterations = 1000;        // outer iterations per curve of Figure 5
  int correspondence_samples = 300;  // ground-truth samples per pair for the point-map error (0: skip)
  ProgressFn progress;
  std::function<void(const std::string&)> note;  // one line of progress text
  const Communicator* communicator = nullptr;    // the ranks sharing the work; nullptr: this process
};

struct PaperExperimentSummary {
  double seconds = 0;
  int shapes = 0;
  long canonical_forms_computed = 0, canonical_forms_cached = 0;  // over all ranks
  long pairs_computed = 0, pairs_cached = 0;                      // over all ranks
  bool figures_drawn = false;  // the PNGs beside report.md (PaperReport::figures_note says why not)
  // Files that could not be used (stage "read") and shapes whose canonical form failed by some method, each
  // left out by every method; and, each shape kept, geodesic fallbacks, shapes --resample kept at their own
  // resolution (stage "resample") and queries of the same bytes as another (stage "dataset"). Empty when
  // nothing failed (rank 0's account; pipeline/shape_failures.h).
  std::vector<ShapeFailure> failures;
};

// What the experiment measured, gathered for report.md.
struct PaperReport {
  PaperExperimentOptions options;  // what was run (its callbacks unused by the report)
  struct ShapeRow {
    std::string name, class_name;
    bool noisy = false, in_retrieval = true;
    Index vertices = 0;
    std::string source;                          // noisy shapes glued here: their clean pose
    std::string defects;                         // mesh/mesh_defects.h summary, "none" for a clean mesh
    std::map<std::string, std::string> repairs;  // per method: what was repaired ("" or absent: nothing)
  };
  std::vector<ShapeRow> shapes;
  struct Skipped {
    std::string file, reason;
  };
  std::vector<Skipped> skipped;  // files of the data that could not be used, and why
  struct Retrieval {
    double map = 0, nn = 0, ft = 0, st = 0, e = 0, dcg = 0;
    double noisy_query_nn = -1;  // nearest-neighbour rate of the noisy queries alone (−1: none)
  };
  std::map<std::string, Retrieval> retrieval;  // per method, under the paper's (Hausdorff) distance
  // Per method, then per distance kind between canonical forms after ICP (hausdorff, chamfer, rmse:
  // matching/shape_distance.h): a conclusion that depends on the choice of distance shows here.
  std::map<std::string, std::map<std::string, Retrieval>> retrieval_by_distance;
  struct MethodCost {
    std::vector<double> precompute, solve;
    std::vector<int> iterations;
    // Peak memory of the process that computed each form (bytes): a method from outside by the command door;
    // −1 for the library's methods, which run inside cshapes.
    std::vector<double> peak_bytes;
  };
  std::map<std::string, MethodCost> cost;
  struct NoiseRow {
    std::string shape, method;
    double vertexwise_rms = 0;  // same vertices, best rigid fit (reflection allowed), / bbox diagonal
    double hausdorff = 0;       // after ICP, / bbox diagonal
    double icp_rmse = 0;        // after ICP, / bbox diagonal
  };
  std::vector<NoiseRow> noise;
  std::map<std::string, double> pose_variation;  // median ICP RMSE between clean poses of a class / diagonal
  std::map<std::string, std::vector<double>> correspondence_mean_error;  // per pair, / √area
  int correspondence_pairs = 0;
  std::vector<TimingRow> table1;
  std::string table1_note;
  struct Convergence {
    int projection_steps = 0;
    double final_energy = 0, final_violation = 0;
  };
  std::vector<Convergence> convergence;
  std::string figure_shape;                                // the shape of Figures 3 and 5
  nlohmann::json figure_grids = nlohmann::json::object();  // Fig. 2, 3 mesh grids for paper_figures.py
  // The figures this run has data for ("fig2_hand", …, "fig9_correspondence"), in order: what
  // paper_figures.py draws (figures.json "draw") and what report.md may link.
  std::vector<std::string> figures;
  bool figures_drawn = false;  // the PNGs exist (paper_experiment drew them)
  std::string figures_note;    // why not, and how to draw them, when not drawn
  std::map<std::string, double> stage_seconds;
  PaperExperimentSummary summary;
  bool resampled = false;
  ResampledDataset resampling;  // with options.resample: the remeshes and their measures
};

// The measurement: the shapes, their canonical forms, ICP distances, retrieval, the noise effect, point maps,
// the figures' data and Table 1, with their data files under options.out (canon/, distances/, metrics.json,
// labels.csv, noise_effect.csv, correspondence_error.csv, point_map_pairs.csv, figures.json, table1.csv,
// convergence.csv) and its caches; returns what report.md says (report.summary: the counts and failures).
// Writes no report.md. On ranks other than 0 of a distributed run, only report.summary's counts are filled.
PaperReport run_paper_experiment(const PaperExperimentOptions& options);

// Draws the figures from the files run_paper_experiment wrote into options.out (paper_figures.py): sets
// report.figures_drawn, or report.figures_note to why not and the command that draws them.
void draw_paper_figures(PaperReport& report);

// The experiment as `cshapes experiment paper` (and cshapes.experiment_paper) runs it: run_paper_experiment,
// the figures (options.draw) and report.md (experiments/paper_report.h) on rank 0. Returns the summary.
PaperExperimentSummary paper_experiment(const PaperExperimentOptions& options);

}  // namespace cshapes
