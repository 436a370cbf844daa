// `cshapes experiment invariance`: how much each method's canonical form changes under transformations of its
// input that must not change it, beside how much it changes between two poses (noise against signal).
//
// For every resolution of options.vertices (0: the shapes as given; N: every shape remeshed to about N
// vertices first, pipeline/resampled_dataset.h, cached under OUT/cache/remeshed, written to OUT/resampled/N),
// every shape of the dataset (or of options.shapes) is the reference mesh, and every method's form of it is
// compared with its form of:
//   - the exact transformations of experiments/invariance_transforms.h: vertex renumbering (options.seeds
//     seeds: seed, seed + 1, ...), face order, a rigid motion, uniform scale ×1e-6 and ×1e3, a jitter of
//     1e-9 × the bounding-box diagonal (one seed each: options.seed). The vertex correspondence is known:
//     RMSE over corresponding vertices after the best rigid fit (Kabsch, reflections allowed), Hausdorff
//     after that same fit;
//   - reported apart, the input remeshed to 0.8× and 1.2× the reference's vertex count (the input surface,
//     not the reference mesh, is remeshed, by the same remesher and cache): no correspondence, RMSE and
//     Hausdorff after ICP, as `cshapes align` reports them. These should change the form little, not nothing.
// All as fractions of the reference form's bounding-box diagonal.
//
// The signal: per method and resolution, its pose variation, the median over every pair of clean poses of one
// class among the run's shapes of the RMSE after ICP between their reference forms (over the mean of the two
// forms' diagonals): the distance retrieval sees between poses (matching/shape_distance.h). ICP rather than
// ground-truth correspondence, so that any dataset with classes has it at any resolution; it is a lower
// bound of the correspondence RMSE, which makes the tolerance below the stricter one.
//
// The verdict, per method and resolution: pass when every exact transformation's RMSE is at most
//   tolerance = max(tolerance_floor_percent % of the diagonal, tolerance_pose_percent % of the pose
//   variation)
// (the floor alone when no two poses of a class are in the run), and every transformed form was computed
// (a method that fails on a transformed mesh but not on its reference fails; a forms-door method that lacks
// the form of a transformed mesh is not measured there, its forms listed in OUT/forms-needed). "all": pass at
// every resolution. The remeshes have no verdict. Each form's convergence (Coulomb's `converged`, SMACOF's
// stop reason; other methods have none) is recorded per row, and the forms that did not converge counted.
//
// Method failures (pipeline/shape_failures.h): a form that fails is named by the shape and the case ("cat0
// (1000 vertices, renumber seed 2)") in result.failures and the run goes on without it; the geodesic
// fallbacks and form-quality records of the reference meshes and remeshes are kept too (those of the exact
// transformations repeat their reference's and are not). Each case's mesh is given to methods under a name
// of its own (the shape's, then "-vN" for a resolution and "-CASE": "cat0-v1000-renumber-2"), so a forms-door
// method (NAME=forms:DIR) finds DIR/cat0.ply for the reference as given and lists the others it lacks in
// OUT/forms-needed/NAME.csv with their meshes.
//
// Outputs (atomic), written by run_invariance_experiment: OUT/invariance.csv (one row per resolution, shape,
// method, transformation and seed), OUT/invariance_pose.csv (one row per resolution, method and pair of
// poses), OUT/invariance_summary.csv (per resolution, method and transformation: medians and maxima, with the
// method's pose variation and tolerance), OUT/invariance.json (everything the report says); by
// draw_invariance_figure OUT/invariance.png (experiments/plots/invariance_figure.py); by
// write_invariance_report OUT/invariance.md. Forms are cached in OUT/cache/forms: a rerun resumes.
#pragma once

#include <cmath>
#include <cstdint>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "cshapes/data/dataset.h"
#include "cshapes/matching/icp.h"
#include "cshapes/pipeline/canonical_form_methods.h"
#include "cshapes/pipeline/shape_failures.h"
#include "cshapes/support/option_limits.h"
#include "cshapes/support/progress.h"
#include "cshapes/support/figure_format.h"

namespace cshapes {

// The limits of the options a user sets (support/option_limits.h), named as on the command line.
namespace invariance_limits {
inline constexpr Limit kSeeds = integer_limit("seeds", 1, 1000);
inline constexpr Limit kSeed = integer_limit("seed", 0, 1e15);
// Each resolution: 0 (as given) or a vertex count from kSmallestResolution (its 0.8× remesh still a mesh).
inline constexpr Limit kVertices = integer_limit("vertices", 0, 1e8);
inline constexpr Index kSmallestResolution = 10;
inline constexpr Limit kToleranceFloor = number_limit("tolerance-floor", 0, 100);
inline constexpr Limit kTolerancePose = number_limit("tolerance-pose", 0, 100);
}  // namespace invariance_limits

// The experiment's own options, each declared once (support/option_declaration.h): `cshapes experiment
// invariance`'s flags and experiment_invariance()'s keywords.
namespace invariance_options {
inline const OptionDeclaration kVertices{
    "vertices", "--vertices",
    "the resolutions (a list; comma-separated on the command line): each shape remeshed to about N vertices "
    "first (cached; OUT/resampled/N), 0 the shapes as given"};
inline const OptionDeclaration kSeeds{"seeds", "--seeds", "vertex renumberings per shape and resolution",
                                      invariance_limits::kSeeds};
inline const OptionDeclaration kSeed{"seed", "--seed",
                                     "the first renumbering's seed (the next ones count up), and the face "
                                     "order's, rigid motion's and jitter's",
                                     invariance_limits::kSeed};
inline const OptionDeclaration kToleranceFloor{
    "tolerance_floor", "--tolerance-floor",
    "verdict: an RMSE up to this % of the diagonal passes (or up to {tolerance_pose}, the larger)",
    invariance_limits::kToleranceFloor};
inline const OptionDeclaration kTolerancePose{
    "tolerance_pose", "--tolerance-pose",
    "verdict: an RMSE up to this % of the method's median pose variation passes",
    invariance_limits::kTolerancePose};
inline const OptionDeclaration kData{"data", "--data",
                                     kDataOption.help + "; two clean poses of a class give a pose pair"};
inline const OptionDeclaration kDraw =
    negated_option("draw", "--no-draw", "draw invariance.png (drawing needs Python with matplotlib)");
inline const std::vector<const OptionDeclaration*> kAll = {&kDraw, &kVertices,       &kSeeds,
                                                           &kSeed, &kToleranceFloor, &kTolerancePose};
}  // namespace invariance_options

// The remeshes reported apart: factors of the reference's vertex count.
inline constexpr double kInvarianceRemeshFactors[] = {0.8, 1.2};

struct InvarianceOptions {
  std::string data;  // folder of meshes, manifest.csv or .cla (data/dataset.h); classes give the pose pairs
  std::string out;   // output folder (its cache/ makes reruns resume)
  // Write into `out` although it holds files cshapes did not write (support/output_folder.h); they stay.
  bool force = false;
  // Read manifest or .cla entries outside the dataset's folder (data/dataset.h: read_dataset).
  bool allow_outside = false;
  std::vector<std::string> methods = canonical_form_methods();  // every registered method
  std::vector<std::string> shapes;  // only these shape names, in the dataset's order; empty: every shape
  // Resolutions, in this order: 0 the shapes as given, N every shape remeshed to about N vertices.
  std::vector<Index> vertices = {0};
  int seeds = 3;           // vertex renumberings per shape and resolution (seeds seed, seed + 1, ...)
  std::uint64_t seed = 1;  // the first renumbering's seed, and the face order's, rigid motion's and jitter's
  double tolerance_floor_percent = 0.05;  // the verdict's tolerance: at least this % of the diagonal ...
  double tolerance_pose_percent = 1;      // ... or this % of the method's median pose variation, the larger
  // Method options (the method field is set per method; MDS geodesics: canon.geodesics, heat by default).
  CanonicalFormOptions canon = experiment_canonical_form_options();
  IcpOptions icp;  // the alignment of the remeshes' forms and of the pose pairs (`cshapes align`'s defaults)
  // draw_invariance_figure draws OUT/invariance.png; false: it records "not requested (--no-draw)" instead.
  bool figure = true;
  // The figure's format: png, pdf or svg (support/figure_format.h).
  FigureFormat figure_format = FigureFormat::png;
  ProgressFn progress;  // stage "invariance": (cases done, cases) over every resolution and shape
  NoteFn note;          // one line per shape and resolution
};

struct InvarianceRow {   // one form against its reference
  Index resolution = 0;  // the resolution asked for (0: as given)
  std::string shape, method;
  std::string transformation;      // to_string(ExactTransform), or "remesh-0.8", "remesh-1.2"
  bool exact = true;               // an exact transformation (false: a remesh, compared by ICP)
  long long seed = -1;             // −1: not seeded (the scales, the remeshes)
  Index vertices = 0;              // of the transformed mesh
  double rmse = 0, hausdorff = 0;  // fractions of the reference form's diagonal
  int converged = -1;              // the transformed form: 1, 0, −1 when the method has no convergence test
  int reference_converged = -1;    // likewise, the reference form
  double seconds =
      0;  // what computing the transformed form took (its pre-computation and solve, as computed)
};

struct InvariancePosePair {  // two poses of one class, one method, one resolution
  Index resolution = 0;
  std::string method, a, b, class_name;
  double rmse = 0, hausdorff = 0;  // after ICP, fractions of the mean of the two forms' diagonals
};

struct InvarianceSummaryRow {  // one resolution, method and transformation, over shapes and seeds
  Index resolution = 0;
  std::string method, transformation;
  bool exact = true;
  int count = 0;
  double median_rmse = NAN, max_rmse = NAN, median_hausdorff = NAN, max_hausdorff = NAN;
};

struct InvarianceVerdict {  // one method at one resolution (resolution −1: every resolution)
  Index resolution = 0;
  std::string method;
  int pose_pairs = 0;
  double pose_rmse = NAN, pose_hausdorff = NAN;  // medians over the pose pairs; NaN: none
  double tolerance = NAN;                        // fraction of the diagonal (see above)
  int measured = 0;                              // exact rows
  double worst_rmse = NAN;                       // the largest exact RMSE
  std::string worst;                             // where: "cat0, renumber seed 2 (1000 vertices)"
  int failed_forms = 0;     // transformed forms that failed where the reference form did not
  int missing_forms = 0;    // transformed forms a forms-door method lacks (not measured, not failed)
  int converged_known = 0;  // forms with a convergence test (references and transformed)
  int not_converged = 0;    // of them, those that did not converge
  std::string verdict;      // "pass", "fail", "not measured"
  std::string reason;       // why it failed or was not measured ("" for a pass)
};

struct InvarianceResult {
  std::vector<Index> resolutions;  // options.vertices
  std::vector<std::string> methods, shapes;
  std::vector<InvarianceRow> rows;
  std::vector<InvariancePosePair> pose_pairs;
  std::vector<InvarianceSummaryRow> summary;  // per resolution, method, then transformation in CSV order
  std::vector<InvarianceVerdict> verdicts;    // per method: each resolution, then "all" (resolution −1)
  std::vector<ShapeFailure> failures;
  std::string figure;          // "invariance.png" (.pdf, .svg: options.figure_format) when drawn, else ""
  std::string figure_problem;  // why not
  double seconds = 0;
};

// The measurement (see above) and its data files; no figure, no report. Throws cshapes::Error for options out
// of their limits, an unknown method or shape name, or a dataset that cannot be read.
InvarianceResult run_invariance_experiment(const InvarianceOptions& options);

// The result as JSON (OUT/invariance.json, `--json`): {experiment, data, resolutions, methods, shapes,
// tolerance {floor_percent, pose_percent}, verdicts, summary, figure, figure_problem, failures}; rmse and
// hausdorff values in % of the diagonal (keys *_percent), null where not measured.
nlohmann::json invariance_json(const InvarianceResult& result, const InvarianceOptions& options);
// invariance.md's text: the verdicts, per resolution the table of the exact transformations (largest RMSE
// per method) beside the pose variation and tolerance, the remeshes apart, convergence, the figure, the
// failures.
std::string invariance_markdown(const InvarianceResult& result, const InvarianceOptions& options);
void write_invariance_report(const InvarianceResult& result, const InvarianceOptions& options);

// Draws options.out/invariance.png from invariance.csv and invariance.json when options.figure; records the
// outcome in result.figure / result.figure_problem (not being able to draw is not an error).
void draw_invariance_figure(InvarianceResult& result, const InvarianceOptions& options);

// The experiment as `cshapes experiment invariance` and cshapes.experiment_invariance run it: the output
// folder claimed (support/output_folder.h), run_invariance_experiment, the figure, the report, the outside
// methods' records, committed.
InvarianceResult invariance_experiment(const InvarianceOptions& options);

}  // namespace cshapes
