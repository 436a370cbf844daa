// `cshapes experiment pose`: how much of the pose variation each canonical form removes, measured with
// ground-truth correspondences instead of retrieval, and how faithful each form is to the surface's metric.
//
// Pairs of poses of one shape with known corresponding vertices:
//   - a TOSCA-style folder (NAME.off + corres/NAME.vts, class = name without trailing digits): every pair of
//     poses of a class; sample s is vertex vts_A[s] of A and vts_B[s] of B (evenly thinned to `samples`);
//   - a TOPKIDS-style folder (kid00.off + kidNN.off + kidNN_ref.txt: "vertex of kidNN, vertex of kid00",
//     1-based): every kidNN against kid00, over the listed vertices;
//   - any other dataset (a folder without corres/, or a manifest.csv; data/dataset.h) whose clean poses of a
//     class share their faces, as `cshapes generate dataset` writes them: every pair of clean poses of a
//     class, vertex i against vertex i (a class whose poses do not share faces is refused).
// Per pair and form (the two inputs themselves, and the canonical forms of each method):
//   pose RMS = sqrt(mean_s ‖R·a_s + t − b_s‖²) / ((diag A + diag B) / 2)
// after the best rigid fit of the samples (Kabsch; reflections allowed, since MDS forms are defined only up
// to one), diag = the bounding-box diagonal of the form. 0: the two poses have the same canonical form up to
// a rigid motion. "Removed" = 1 − form RMS / input RMS: the share of the pose variation the method undoes.
// Per shape and form, the metric faithfulness: edge stretch ‖x_i − x_j‖ / ‖v_i − v_j‖ over the edges not
// torn (mean |stretch − 1|, 99th percentile and max), and the geodesic stress against fast-marching distances
// from `stress_sources` sources: sqrt(Σ (‖x_i − x_s‖ − g_is)² / Σ g_is²) over all vertices i and sources s
// (the normalised stress MDS minimises, measured the same way for every method).
//
// Resampling (options.resample.vertices > 0, `--resample N`): every shape is remeshed to about N vertices
// first (pipeline/resampled_dataset.h, cached under OUT/cache/remeshed, written to OUT/resampled) and its
// forms are computed on the remesh, which keeps none of the input's vertices. Each correspondence sample (a
// vertex of the input) is carried to the remesh as the closest point of the remeshed surface
// (mesh/locate_on_surface.h), and a form's position of the sample is the form interpolated there
// (barycentric, on the remesh's triangle); the input's pose RMS likewise compares the located points on the
// two remeshes. For a dataset whose poses share faces, the pair is still vertex i of input A against vertex i
// of input B, each located on its own remesh (the remeshes share no faces). Edge stretch and geodesic stress
// are measured on the remesh. The report gives the remeshes' measures and how far the located points lie from
// the input vertices. What this separates: the pose invariance of a form at another resolution, on the same
// surfaces and truth.
//
// Where the pose stays (options.parts): the parts of each class are found on its first pose (in shape order;
// TOPKIDS: kid00) from its geometry alone (geodesics/geodesic_parts.h: a geodesic centre, the extremities as the
// persistent maxima of the distance from it, each vertex in its nearest extremity's part when within half
// that extremity's distance to the centre, else in the core), and carried to the other poses through the
// ground truth: a sample's part is that of its vertex on the first pose (through the pairs with the first
// pose; a sample the truth does not reach has part −1, "unassigned"). Per pair, form and part: the RMS of the
// residuals ‖R·a_s + t − b_s‖ of the part's samples after the pair's whole-shape rigid fit (the same fit as
// the pose RMS, not one per part), over the same mean diagonal; so the parts' mean squares, weighted by their
// samples, add up to the whole pose RMS². Parts are named by index and by their extremity's vertex on the
// first pose ("part 2 (extremity at vertex 1234 of cat0)"); nothing says which is a hand.
//
// The figure (draw_pose_figure, experiments/plots/pose_figure.py): for one pair, the pair with the median
// Coulomb pose RMS (the first method's when Coulomb is not run, the input's when no method is), one panel per
// form, pose b's samples at its input positions coloured by their residual after the fit, one colour scale,
// % of the mean diagonal. Its data: OUT/pose_residuals.csv (a row per sample) and OUT/pose_residuals.json
// (the pair, why it was chosen, each form's pose RMS).
//
// Canonical forms are cached under OUT/cache (a rerun, or a second run with other Coulomb options, computes
// only what changed); MDS methods share one geodesic matrix per shape. Outputs (atomic): run_pose_invariance
// writes the data, OUT/pose_pairs.csv (one row per pair and form), OUT/pose_shapes.csv (one row per shape and
// form), OUT/pose_summary.csv (per form: medians over pairs, overall and per class), OUT/pose_parts.csv (one
// row per pair, form and part: config,a,b,class,form,part,parts_shape,extremity_vertex,samples,rms, the
// PosePartRow fields with the shape the parts were found on and the part's extremity vertex there, 0-based,
// empty for the core and the unassigned) and the figure's data (OUT/pose_residuals.csv:
// sample,vertex,x,y,z,part and a residual column per form; OUT/pose_residuals.json: PoseFigurePair's a, b,
// class, chosen_by, forms, titles and rms per form); draw_pose_figure draws OUT/pose_residuals.png;
// write_pose_invariance_report writes OUT/pose.md (the summary as a table, the per-part table, the figure)
// from the result.
#pragma once

#include <functional>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "cshapes/geodesics/geodesic_parts.h"
#include "cshapes/pipeline/canonical_form_methods.h"
#include "cshapes/pipeline/resampled_dataset.h"
#include "cshapes/pipeline/shape_failures.h"
#include "cshapes/support/figure_format.h"

namespace cshapes {

// The experiment's own options, each declared once (support/option_declaration.h): `cshapes experiment
// pose`'s flags and experiment_pose()'s keywords.
namespace pose_experiment_options {
inline const OptionDeclaration kSamples{"samples", "--samples",
                                        "ground-truth correspondences per pair (evenly spaced; 0: all)"};
inline const OptionDeclaration kData{"data", "--data",
    "folder: NAME.off + corres/NAME.vts (pairs within a class), or kid00.off + kidNN.off + kidNN_ref.txt (every "
    "kidNN against kid00), or a dataset (folder or manifest.csv) whose clean poses of a class share their faces "
    "(vertex i against vertex i)"};
inline const OptionDeclaration kDraw =
    negated_option("draw", "--no-draw", "draw pose_residuals.png (drawing needs Python with matplotlib)");
inline const OptionDeclaration kParts =
    negated_option("parts", "--no-parts", "report the residuals per part (pose_parts.csv)");
}  // namespace pose_experiment_options

struct PoseInvarianceOptions {
  std::string data;  // TOSCA-style or TOPKIDS-style folder, or a shared-connectivity dataset (see above)
  std::string out;   // output folder (its cache/ makes reruns resume)
  // Write into `out` although it holds files cshapes did not write (support/output_folder.h); they stay.
  bool force = false;
  // Read manifest or .cla entries outside the dataset's folder (data/dataset.h: read_dataset).
  bool allow_outside = false;
  std::vector<std::string> methods = canonical_form_methods();  // every registered method
  // Restrict to these shape names (e.g. a tuning half); empty: every shape of the folder.
  std::vector<std::string> shapes;
  int samples = 1000;       // ground-truth correspondences per pair, evenly spaced; ≤ 0: all
  int stress_sources = 16;  // sources of the geodesic stress (evenly spaced vertex indices); 0: skip
  // vertices > 0: every shape remeshed to about that many vertices first, the samples carried to the remesh
  // (see above; the report's "Resampling" section); 0: the shapes as they are.
  ResampleOptions resample;
  std::string label;  // a name for this run's configuration, written into every CSV row
  // Method options (the method field is set per method; MDS geodesics: canon.geodesics, heat by default).
  CanonicalFormOptions canon = experiment_canonical_form_options();
  bool parts = true;                 // the per-part breakdown (see above); false: none
  GeodesicPartsOptions part_finder;  // how the parts are found on each class's first pose
  // draw_pose_figure draws OUT/pose_residuals.png; false: it records "not requested (--no-draw)" instead.
  bool figure = true;
  // The figure's format: png, pdf or svg (support/figure_format.h).
  FigureFormat figure_format = FigureFormat::png;
  std::function<void(const std::string&)> note;  // one line per shape and pair
};

// One class's parts, found on its first pose (geodesics/geodesic_parts.h).
struct PoseClassParts {
  std::string class_name, shape;           // shape: the class's first pose, where the parts were found
  int centre = -1;                         // vertex of `shape` (0-based)
  std::vector<int> extremities;            // vertices of `shape` (0-based); part k is extremities[k − 1]
  std::vector<double> reach, persistence;  // per extremity, over the largest distance from the centre
  std::string repair_text;                 // what the repair for the part finder's geodesics did
  std::string problem;                     // why the class has no parts ("" when it has)
};

struct PosePartRow {  // one pair, one form, one part
  std::string a, b, class_name, form;
  int part = 0;     // 0 the core, k ≥ 1 extremity k's part, −1 samples with no part (unassigned)
  int samples = 0;  // the pair's samples in the part, finite in both forms
  double rms = 0;   // RMS residual after the pair's whole-shape rigid fit, over the mean diagonal
};

struct PosePartSummaryRow {  // one class, form and part, over the pairs
  std::string class_name, form;
  int part = 0;
  int pairs = 0;
  double median_samples = 0;  // median over pairs of the part's samples
  double median_rms = 0;      // median over pairs of the part's RMS
};

// The pair the figure shows and its per-sample residuals.
struct PoseFigurePair {
  std::string a, b, class_name;
  std::string chosen_by;  // "the pair with the median Coulomb pose RMS (4th of 9)"
  std::vector<std::string> forms;
  std::vector<double> rms;    // per form: its pose RMS
  std::vector<int> vertices;  // per sample: vertex of b's input
  Points positions;           // per sample: b's input position there
  std::vector<int> parts;     // per sample: its part (−1 unassigned)
  Eigen::MatrixXd residuals;  // samples × forms: residual after the fit, over the mean diagonal (NaN: none)
};

struct PosePairRow {
  std::string a, b, class_name, form;  // form: "input" or a method
  double rms = 0;                      // pose RMS (see above), a fraction of the diagonal
  double input_rms = 0;                // the same for the inputs
  int samples = 0;
};

struct PoseShapeRow {
  std::string shape, form;
  double mean_abs_stretch = 0, p99_stretch = 0, max_stretch = 0;
  double stress = -1;  // geodesic stress; −1 when not measured
  int iterations = 0;
  double seconds = 0;
  int torn_edges = 0;
};

struct PoseSummaryRow {
  std::string form, class_name;  // class_name "all" for every pair
  int pairs = 0;
  double median_rms = 0, mean_rms = 0, median_input_rms = 0;
  double removed = 0;                                         // 1 − median_rms / median_input_rms
  double mean_abs_stretch = 0, max_stretch = 0, stress = -1;  // medians over the shapes (max: the worst)
};

// With resampling: how far one shape's correspondence samples moved when carried to its remesh.
struct PoseLocatedRow {
  std::string shape;
  int samples = 0;           // input vertices that are a sample of some pair (each located once)
  double mean_distance = 0;  // mean ‖input vertex − located point‖ over the input's bounding-box diagonal
  double max_distance = 0;  // the largest, likewise
  // Samples closest to another part of the surface (an arm lying against the body), located on their own
  // part instead (relocated), or left there for want of a triangle of their own within reach
  // (pipeline/remesh_samples.h).
  int relocated = 0, off_part = 0;
  bool remeshed = true;  // false: the shape was kept at its own resolution (its samples are its vertices)
};

struct PoseInvarianceResult {
  std::vector<PosePairRow> pairs;
  std::vector<PoseShapeRow> shapes;
  std::vector<PoseSummaryRow> summary;  // per form ("input" first, then the methods), "all" and per class
  // Shapes whose canonical form failed by some method, left out with every pair they are in; geodesic
  // fallbacks, shapes --resample kept at their own resolution and poses of the same bytes as another (each
  // kept): pipeline/shape_failures.h; listed at the end of pose.md when not empty.
  std::vector<ShapeFailure> failures;
  bool resampled = false;                        // options.resample.vertices > 0
  ResampledDataset resampling;                   // when resampled: the remeshes and their measures
  std::vector<PoseLocatedRow> located;           // when resampled: per shape, in shape order
  std::vector<PoseClassParts> classes;           // options.parts: per class, in shape order
  std::vector<PosePartRow> parts;                // options.parts: per pair, form and part
  std::vector<PosePartSummaryRow> part_summary;  // per class, part and form
  PoseFigurePair figure_pair;                    // empty a, b when no pair was measured
  std::string figure;          // "pose_residuals.png" (.pdf, .svg) when draw_pose_figure drew it, else ""
  std::string figure_problem;  // why it was not drawn
};

// The measurement (see above): discovers the shapes and pairs (throws on a malformed folder or
// correspondence file, naming it), computes or reads from OUT/cache every form, and writes the three CSV
// files into options.out. No report.
PoseInvarianceResult run_pose_invariance(const PoseInvarianceOptions& options);

// pose.md's text from the result and the options it was run with (label, data, samples, stress sources): the
// summary table (pose RMS as percentages of the diagonal, "—" for a value not measured), with resampling the
// remeshes' measures and the located samples' distances, and the shapes left out. The shapes and pairs it
// counts are those of the result (shapes left out are not).
std::string pose_invariance_markdown(const PoseInvarianceResult& result,
                                     const PoseInvarianceOptions& options);
// The summary as JSON (`cshapes experiment pose --json`): {"shapes", "pairs", "summary": [{form, class,
// pairs, median_rms, mean_rms, median_input_rms, removed, mean_abs_stretch, max_stretch, stress (null: not
// measured)}], "figure", "figure_problem", "failures"}; rms values are fractions of the bounding-box diagonal.
nlohmann::json pose_invariance_json(const PoseInvarianceResult& result);
// Writes it to folder/pose.md.
void write_pose_invariance_report(const PoseInvarianceResult& result, const PoseInvarianceOptions& options,
                                  const std::string& folder);

// Draws options.out/pose_residuals.png from the data files run_pose_invariance wrote, when options.figure,
// and records the outcome in result.figure / result.figure_problem (a figure that cannot be drawn is not an
// error: figure_problem says why).
void draw_pose_figure(PoseInvarianceResult& result, const PoseInvarianceOptions& options);

// The experiment as `cshapes experiment pose` runs it: run_pose_invariance, draw_pose_figure, then
// write_pose_invariance_report into options.out.
PoseInvarianceResult pose_experiment(const PoseInvarianceOptions& options);

}  // namespace cshapes
