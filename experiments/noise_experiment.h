// `cshapes experiment noise`: how each method's canonical forms and retrieval respond to growing topological
// noise (issue 11, item 3; the paper's claim of §3 and Figs. 2, 7, 8: Coulomb shapes are "drastically less
// sensitive to topological noise" than MDS canonical forms).
//
// Every clean pose of the data (per class: all, or the first poses_per_class that can be used) is glued at
// each level K of `levels` (0, 1, 2, 4, 8 by default) with data/topological_noise.h — the glue of
// `experiment paper`: short tubes between spots close in space and far along the surface. Each (pose, level)
// has its own seed, derived from options.seed, the pose's name and K (glue_seed), so levels are independent
// draws and adding a pose or a level changes no other glued mesh. Each glue adds one handle, so on the glued
// mesh χ' = χ − 2K (the noise module's contract, checked here with mesh_info on every glued mesh: a mismatch
// is reported and the mesh left out of every measurement). Level 0 is the clean pose itself.
//
// Per method (pipeline/canonical_forms.h, cached in out/cache/forms) and level:
//   a) retrieval of noisy queries among clean shapes: the query is pose p glued at level K; the database is
//      every clean pose except p itself (so the query's own clean twin never answers), relevant = same
//      class; the distance between two shapes is the ICP shape distance of their canonical forms
//      (eval/pairwise_distances.h, cached in out/cache/pairs) under each of Hausdorff (the paper's), Chamfer
//      and RMSE (matching/shape_distance.h). Reported: mAP and the nearest-neighbour rate over queries, with
//      the average precision of eval/retrieval.h ((1/R) Σ_k k / rank_k, ties by database order). Level 0 is
//      the clean leave-one-out retrieval. A class with a single usable pose gives no query (nothing
//      relevant).
//   b) the noisy form against its own clean pose's form, at the same vertices: aligned_rms (mesh/
//      rigid_transform.h: best rigid fit, reflections allowed) over the clean form's bbox diagonal; median
//      and mean over poses. 0 at level 0 (the same mesh has the same cached form).
//
// Outputs under options.out: noise.csv (one row per method, level and distance kind), noise.json (the same
// plus every glued mesh's seed and χ check and every per-query value), shapes/NAME_glueK.off (the glued
// meshes), noise.png drawn by options.figure_script when an interpreter with matplotlib is found, and
// report.md. Everything expensive is cached under out/cache (forms, pairs, glued meshes), so a killed run
// resumes and a rerun computes nothing.
//
// Cost per method: one canonical form per (pose, level) — P·|levels| — and P·(P−1)/2 + P·(P−1)·(|levels|−1)
// ICP pairs at most (P clean poses; only pairs within the database are aligned). tosca5k (24 poses, 5
// levels): 120 forms and about 2,500 pairs per method.
#pragma once

#include <cstdint>
#include <functional>
#include <limits>
#include <map>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "cshapes/data/dataset.h"
#include "cshapes/pipeline/canonical_form_methods.h"
#include "cshapes/pipeline/resampled_dataset.h"
#include "cshapes/pipeline/shape_failures.h"
#include "cshapes/support/figure_format.h"

namespace cshapes {

// The experiment's own options, each declared once (support/option_declaration.h): `cshapes experiment
// noise`'s flags and experiment_noise()'s keywords.
namespace noise_experiment_options {
inline const OptionDeclaration kLevels{"levels", "--levels",
                                       "glue counts, one noisy version of every clean pose per count (0: the "
                                       "clean shape); a list, comma-separated "
                                       "on the command line"};
inline const OptionDeclaration kSeed{"seed", "--seed",
                                     "base seed of the glues (each pose and level derives its own)"};
inline const OptionDeclaration& kData = kDataOption;
inline const OptionDeclaration kDraw =
    negated_option("draw", "--no-draw", "draw noise.png (drawing needs Python with matplotlib)");
inline const std::vector<const OptionDeclaration*> kAll = {&kLevels, &kSeed, &kDraw};
}  // namespace noise_experiment_options

struct NoiseExperimentOptions {
  std::string data;  // folder of meshes or manifest.csv; shapes the data marks noisy are not used
  std::string out;   // output folder (its cache/ makes reruns resume)
  // Write into `out` although it holds files cshapes did not write (support/output_folder.h); they stay.
  bool force = false;
  // Read manifest or .cla entries outside the dataset's folder (data/dataset.h: read_dataset).
  bool allow_outside = false;
  // vertices > 0: every shape remeshed to about that many vertices first (pipeline/resampled_dataset.h,
  // into out/resampled; the report's "Resampling" section).
  ResampleOptions resample;
  std::vector<std::string> methods = canonical_form_methods();  // every registered method
  std::vector<int> levels = {0, 1, 2, 4, 8};  // glues per noisy version (distinct, ≥ 0; 0: the clean pose)
  std::uint64_t seed = 1;                     // base of every glue seed (glue_seed)
  int poses_per_class = 0;                    // clean poses per class; ≤ 0: all
  // Gluing: where a pose offers fewer admissible spots than K, widen the gap ×1.5 and lower the geodesic
  // ratio ×0.8 up to this many times (TopologicalNoiseOptions::relax_steps; `experiment paper` uses 3).
  int relax_steps = 3;
  // Method options (canon.method is set per method; MDS geodesics: canon.geodesics, heat by default).
  CanonicalFormOptions canon = experiment_canonical_form_options();
  // Draw noise.png (experiments/plots/noise_figure.py, by experiments/figures.h) after the data is written.
  bool figure = true;
  // The figure's format: png, pdf or svg (support/figure_format.h).
  FigureFormat figure_format = FigureFormat::png;
  ProgressFn progress;                           // stages "canonical forms", "distances"
  std::function<void(const std::string&)> note;  // one line of progress text
};

// One glued mesh: pose `shape` at `level` glues.
struct NoiseGlue {
  std::string shape, class_name;
  int level = 0;
  std::uint64_t seed = 0;
  long chi_before = 0, chi_after = 0, chi_expected = 0;  // Euler characteristics; expected = before − 2·level
  bool ok = true;     // glued and χ as expected; false: left out of the measurements (see error)
  std::string error;  // why not ok: the glue failed (too few admissible spots) or χ mismatched
  int relax_steps_used = 0;
};

// One method, level and distance kind.
struct NoiseRow {
  std::string method;
  int level = 0;
  std::string distance;  // hausdorff | chamfer | rmse
  int queries = 0;       // noisy queries with at least one relevant shape in the database
  double map = 0;        // mean average precision over those queries (NaN when there is none)
  double nn = 0;         // fraction whose nearest database shape has their class
  // Noisy-vs-clean canonical forms (the same for every distance kind): aligned_rms / clean form's bbox
  // diagonal, over the glued poses of this level (form_poses; NaN when none could be glued this often).
  double form_rms_median = 0, form_rms_mean = 0;
  int form_poses = 0;
  // The mAP of the same queries' clean poses (level 0, this distance): the baseline of exactly the poses
  // this level measures, which is fewer than all when some poses offer too few spots. NaN without level 0.
  double map_clean_same_poses = std::numeric_limits<double>::quiet_NaN();
};

// A clean pose of the run, as read.
struct NoisePose {
  std::string name, class_name, file;
  Index vertices = 0;
  long chi = 0;  // Euler characteristic
};

struct NoiseExperimentResult {
  NoiseExperimentOptions options;  // what was run (levels sorted; no callbacks): the report says it
  std::vector<NoisePose> pose_list;  // the clean poses measured, in the data's order
  std::vector<NoiseRow> rows;    // methods × levels × {hausdorff, chamfer, rmse}, in that order
  std::vector<NoiseGlue> glues;  // every (pose, level > 0), in pose then level order
  int poses = 0, classes = 0;
  bool resampled = false;
  ResampledDataset resampling;  // with options.resample: the remeshes and their measures
  int chi_mismatches = 0, glue_failures = 0;
  long glued_computed = 0, glued_cached = 0;
  long canonical_forms_computed = 0, canonical_forms_cached = 0;
  long pairs_computed = 0, pairs_cached = 0;
  bool figure = false;      // noise.png (.pdf, .svg: options.figure_format) was drawn
  std::string figure_note;  // why not, when not
  double seconds = 0;
  // Poses that could not be read and shapes (clean poses or glued versions) whose form failed by some method,
  // left out by every method (a clean pose with its glued versions); geodesic fallbacks, shapes --resample
  // kept at their own resolution and poses of the same bytes as another (each kept). In report.md and
  // noise.json when not empty (pipeline/shape_failures.h).
  std::vector<ShapeFailure> failures;
  std::vector<std::string> skipped;              // files that could not be read, with the reason
  std::map<std::string, double> pose_variation;  // per method: median ICP RMSE of two clean poses of a class
  nlohmann::json per_query;  // method → level → distance → [{query, ap, nn}]
  nlohmann::json form_rms;   // method → level → pose → form RMS
};

// The measurement: glued meshes (the shared glued-mesh cache, pipeline/glued_meshes.h; their files under
// out/shapes), canonical forms and ICP pairs through out/cache, the rows. Writes nothing else; the result is
// the data of every output below.
NoiseExperimentResult run_noise_experiment(const NoiseExperimentOptions& options);
// noise.csv (one row per method, level and distance) and noise.json (also every glue's seed and χ, every
// query's average precision, every pose's form distance), from the result alone.
void write_noise_outputs(const NoiseExperimentResult& result, const std::string& folder);
// report.md from the result alone (result.figure says whether noise.png is there to show).
void write_noise_report(const NoiseExperimentResult& result, const std::string& folder);
// The experiment as `cshapes experiment noise` runs it: run_noise_experiment, write_noise_outputs, noise.png
// (when options.figure; experiments/figures.h), write_noise_report. result.seconds counts all of it.
NoiseExperimentResult noise_experiment(const NoiseExperimentOptions& options);

// The seed of pose `shape` glued at `level`: the first 16 hex digits of SHA-256("noise-glue", seed, shape,
// level) as an integer. Deterministic, and independent between poses and levels.
std::uint64_t glue_seed(std::uint64_t seed, const std::string& shape, int level);

}  // namespace cshapes
