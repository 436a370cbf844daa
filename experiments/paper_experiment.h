// `cshapes experiment paper`: the paper's experiment end to end (§3), and more.
//
// Per class: N near-isometric poses + K topologically noisy shapes (the dataset's own, or made here by gluing
// another pose with core/topological_noise.h); canonical forms by every method (pipeline/canonical_forms.h,
// cached); ICP distances between all pairs (eval/pairwise_distances.h, cached); retrieval measures and PR
// curves (eval/retrieval.h); the effect of topological noise on each method's canonical form; point-map
// errors where ground-truth correspondences exist; the data behind Figures 2-8; Table 1
// (experiments/timing_table.h); report.md. Imperfect meshes are read as they are and repaired per method, said
// per shape in notes and report.md; a file no method can use (unreadable, too few vertices) is skipped with
// its reason. Everything is written under options.out; every expensive intermediate is cached in out/cache,
// so a run that is killed resumes where it stopped. A shape whose canonical form fails by any method is left
// out by every method, named with its reason in summary.failures, report.md and metrics.json (unless
// canon.strict: then the error ends the run); the run goes on with the others.
//
// Distributed (options.communicator with R > 1 ranks, pipeline/distributed.h): the two expensive stages are
// split over the ranks — canonical forms by expected cost (vertex counts, longest first), the ICP pairs of
// each method in blocks of equal count — through the cache in out/cache, which every rank must see. Rank 0
// does everything else and writes every output; the other ranks write nothing but cache entries and return
// after the pairs (their summary holds only the counts). The outputs are those of one process, byte for byte.
#pragma once

#include <functional>
#include <string>
#include <vector>

#include "core/communicator.h"
#include "pipeline/canonical_form_methods.h"
#include "pipeline/shape_failures.h"

namespace cshapes {

struct PaperExperimentOptions {
  std::string data;  // folder of meshes or manifest.csv
  std::string out;   // output folder
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
  bool table1 = true;          // measure Table 1 (remeshes to 3,505 and 22,738 vertices)
  int timing_repeats = 5;      // Table 1: runs per median
  bool figures = true;         // compute the data of Figures 2, 3, 4, 5
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
  // Files that could not be used (stage "read") and shapes whose canonical form failed by some method, each
  // left out by every method; and geodesic fallbacks (the shape kept). Empty when nothing failed (rank 0's
  // account; pipeline/shape_failures.h).
  std::vector<ShapeFailure> failures;
};

PaperExperimentSummary run_paper_experiment(const PaperExperimentOptions& options);

}  // namespace cshapes
