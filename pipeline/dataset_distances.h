// The distance matrix of a whole dataset: each shape's canonical form (cached), ICP between every pair
// (cached), the paper's distances. `cshapes distmat` is this call and a CSV writer; the Python module and
// MPI runs (`mpirun -np R cshapes distmat`) call the same function.
//
// Distributed (options.communicator with R > 1 ranks, pipeline/distributed.h): the shapes are split by
// expected cost (vertex counts, longest first) and each rank canonizes its share into the cache; then every
// rank reads all forms from the cache, the missing pairs are split in blocks of equal count
// (eval/pairwise_distances.h) and the matrices meet on rank 0. The result is bit-identical to one process;
// only rank 0's `distances` holds the matrices. Counts (forms and pairs computed or cached) are over all
// ranks. A distributed run needs a cache folder that every rank sees.
//
// Two-stage mode (two_stage_k = k > 0; off by default, the exact all-pairs matrix is the reference): a
// descriptor of each form (matching/shape_descriptor.h) picks each shape's k nearest candidates, ICP runs
// only on the union of those pairs (each once), and every pair not aligned gets M·(1 + δ) — M the largest
// aligned distance, δ the descriptor distance — so it ranks after every aligned candidate of its row, in
// descriptor order (eval/candidate_pairs.h). With a reference matrix (the exact run's CSV), recall@k is
// reported: the fraction of each shape's true k nearest that its candidates held.
//
// Each shape is repaired for the method (pipeline/canonical_forms.h) or, with canon.strict, refused (the
// error is thrown). A file no method can use (unreadable, too few vertices after repair) or a shape whose
// form fails is skipped with its reason (`failures`, pipeline/shape_failures.h) unless strict; at least two
// usable shapes are needed.
#pragma once

#include <functional>
#include <map>
#include <string>
#include <vector>

#include "cshapes/support/communicator.h"
#include "cshapes/support/stage_time.h"
#include "cshapes/support/option_declaration.h"
#include "cshapes/eval/pairwise_distances.h"
#include "cshapes/matching/shape_descriptor.h"
#include "cshapes/pipeline/canonical_form_methods.h"
#include "cshapes/pipeline/canonical_forms.h"
#include "cshapes/pipeline/resampled_dataset.h"
#include "cshapes/pipeline/shape_failures.h"

namespace cshapes {

// `--two-stage-k K` of `cshapes distmat` and `experiment retrieval`, two_stage_k= in Python (declared once).
inline const OptionDeclaration kTwoStageKOption{
    "two_stage_k", "--two-stage-k",
    "two-stage retrieval: align only each shape's K nearest candidates by a cheap descriptor; other pairs "
    "rank after them (0: all pairs, exact)"};

struct DatasetDistanceOptions {
  std::string data;            // folder of meshes (class = name without trailing digits) or manifest.csv
  bool allow_outside = false;  // read manifest entries outside the dataset's folder (data/dataset.h)
  // The method and its options (canon.name is set per shape): by default the experiments' (heat geodesics for
  // MDS, pipeline/canonical_form_methods.h), so `cshapes distmat` and a C++ caller start from the same options.
  CanonicalFormOptions canon = experiment_canonical_form_options();
  std::string cache_dir;  // canonical forms under cache_dir/forms, pairs under cache_dir/pairs; empty: none
  PairwiseDistanceOptions pairs;                 // ICP options; cache_dir and progress are set here
  ProgressFn progress;                           // stage "distances"
  std::function<void(const std::string&)> note;  // one line per shape (and per repair or skipped file)
  const Communicator* communicator = nullptr;    // the ranks sharing the work; nullptr: this process
  int two_stage_k = 0;                // > 0: align only each shape's k descriptor-nearest candidates
  ShapeDescriptorOptions descriptor;  // two-stage: the descriptor
  std::string reference;              // two-stage: the exact matrix's CSV, for recall@k; empty: none
  // vertices > 0: every shape remeshed to about that size first (pipeline/resampled_dataset.h), into
  // cache_dir/resampled-N (the meshes, manifest.csv, resample.csv), the remeshes cached in cache_dir/remeshed.
  // Needs a cache folder.
  ResampleOptions resample;
};

struct TwoStageSummary {
  int k = 0;                                 // 0: the exact mode ran
  long pairs_aligned = 0;                    // distinct candidate pairs (of N(N−1)/2)
  double recall = -1;                        // recall@k against `reference`; −1 without one
  std::vector<std::vector<int>> candidates;  // per shape, its k candidates, nearest first
};

struct DatasetDistances {
  std::vector<std::string> names;    // usable shapes, in the dataset's order
  std::vector<std::string> classes;  // their classes
  std::vector<std::string> skipped;  // files skipped (not under strict)
  std::vector<std::string> skipped_reasons;
  // Every file skipped (stage "read") or shape whose form failed (left out), and geodesic fallbacks (kept):
  // pipeline/shape_failures.h. Empty when nothing failed.
  std::vector<ShapeFailure> failures;
  long forms_computed = 0, forms_cached = 0;  // over all ranks
  // Per usable shape (names' order): what its form cost when it was computed (pre-computation and embedding,
  // seconds; a cached form keeps the run's that computed it), and the peak memory of the process that computed
  // it (bytes; a method from outside by the command door; −1 where not measured: in-process methods).
  std::vector<double> form_seconds, form_peak_bytes;
  PairwiseDistanceResult distances;  // N×N over `names`: hausdorff (the paper's), chamfer, rmse (rank 0)
  TwoStageSummary two_stage;
  // Where this call's time went (support/timing.h), on this rank: "resample" (with options.resample),
  // "forms" (reading the files, the forms computed or read from the cache) and "pairs" (the candidates of
  // two-stage mode, the alignments and distances), each with the method's name.
  std::vector<StageTime> profile;
  ResampledDataset resampling;  // with options.resample: what was remeshed, and how well (else empty)
};

DatasetDistances dataset_distances(const DatasetDistanceOptions& options);

// Several methods over one dataset (`cshapes experiment retrieval`): the forms of the methods that embed the
// full geodesic matrix (classical MDS and SMACOF at the same geodesic settings), computed shape by shape into
// the cache (options.cache_dir/forms) before the methods' own passes, so that each shape's matrix is computed
// once for all of them (pipeline/canonical_forms.h: cached_canonical_forms shares it). The forms are the
// same bytes a method's own pass computes (the cache keys are the same). dataset_distances then reads them
// from the cache, and meets and reports a shape that failed here (nothing is said or thrown here, unless the
// cache cannot be written). Nothing happens with fewer than two such methods, without a cache, or across
// ranks (options.communicator with R > 1: each method's pass shares its forms over the ranks instead).
// options.data must already be what dataset_distances reads (resampled, when it resamples). Returns the forms
// computed per method, and appends the stage to `profile` ("forms", the methods joined by '+').
std::map<std::string, long> precompute_shared_geodesic_forms(const DatasetDistanceOptions& options,
                                                             const std::vector<std::string>& methods,
                                                             std::vector<StageTime>* profile = nullptr);

}  // namespace cshapes
