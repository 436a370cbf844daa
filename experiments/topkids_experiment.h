// `cshapes experiment topkids`: point maps between poses with REAL topological noise (SHREC'16 "Matching of
// deformable shapes with topological noise", Lähner et al. 2016: shared/data/topkids), scored against ground
// truth by the benchmark's protocol, per canonization method and for the inputs themselves.
//
// Data (a folder): the reference pose REFERENCE.off (kid00; any mesh format mesh/io.h reads), and per query
// pose NAME.off with NAME_ref.txt (eval/correspondence_error.h read_correspondence_pairs: "a b" per line,
// vertex a of NAME ↔ vertex b of the reference, 1-based) and optionally NAME_sym.txt (the same for the
// left-right mirrored truth, for the vertices that have one). Query poses are every NAME_ref.txt of the
// folder but the reference's, in name order, or options.poses.
//
// Per method (pipeline/canonical_forms.h: each mesh repaired for the method, the repair reported; forms
// cached under out/cache/forms, so a killed run resumes): the canonical forms of the reference and of each
// pose; the pose's form aligned onto the reference's by ICP (matching/icp.h with the retrieval's options:
// principal-axis starts, reflections allowed, since canonical forms are defined up to one); the induced map
// sends each vertex of the pose to the nearest vertex of the reference's aligned form
// (IcpResult::source_to_target). The "inputs" row is the same ICP on the meshes as they are (no canonical
// form): the floor a canonical form has to beat. Scoring (eval/correspondence_error.h
// symmetric_correspondence_errors): for each ground-truth vertex v used (options.samples, evenly spaced over
// NAME_ref.txt), the geodesic distance on the reference between map(v) and truth(v) over √area(reference),
// the smaller of that and the distance to the mirrored truth where NAME_sym.txt has one (the benchmark
// forgives a symmetric flip). Geodesics by fast marching on the reference repaired to a manifold: their
// error is below the curves' step (the measurement against exact geodesics: docs/design.md, "Measured
// figures behind choices in the code"). One scoring per pose serves every method; it is cached (out/cache/misc) by
// the forms' keys, the truth files' contents and the options.
//
// The flip is also forgiven per whole map instead (TopkidsRow::whole_map_*), a stricter reading reported
// beside.
//
// Mirrored maps. A map is *mirrored* (TopkidsRow::mirrored) when it is clearly nearer the mirrored truth than
// the truth: its mean error against the mirrored truth (NAME_sym.txt's mirror where there is one, the truth
// elsewhere) is at most kMirroredErrorRatio = ½ of its mean error against the truth alone, both over the same
// mapped samples. A map that mixes the sides, or one unrelated to the truth, is about as far from both and is
// not counted; a pose without NAME_sym.txt is never mirrored. Per method the summary gives the share of poses
// whose map is mirrored, and the median over poses of the pose's mean error beside the pooled mean: with a
// few poses and bimodal errors (a flipped alignment costs 0.2-0.3 per pose) a pooled mean moves with one
// flip, the medians and the share say whether it did.
//
// The mirror files: NAME_sym.txt pairs vertex a of the pose with its left-right mirror b on the pose itself
// (both 1-based vertices of the pose), so a's mirrored truth on the reference is the truth of b (on the
// shared data this equals kid00_sym.txt's mirror of a's truth for every listed vertex).
//
// Resampling (options.resample.vertices > 0, `--resample N`): the reference and every pose are remeshed to
// about N vertices first (pipeline/resampled_dataset.h: cached under out/cache/remeshed, written to
// out/resampled), and the forms and ICP are computed on the remeshes; the ground truth and the scoring stay
// on the inputs. Each ground-truth vertex of a pose is carried to the pose's remesh
// (pipeline/remesh_samples.h: the closest point of the remeshed surface), its position in a form interpolated
// there and moved by the ICP alignment; its image is the nearest vertex of the reference's aligned form,
// taken back to the vertex of the reference input nearest to that remesh vertex. The report gives the
// remeshes' measures, how far the carried vertices moved and how far the reference's remesh vertices lie from
// the input vertices they go to.
//
// Three steps, as `cshapes experiment topkids` runs them:
//   run_topkids_experiment   the measurement; writes the data files into out/: topkids.csv (one row per
//                            method and pose), curves.csv (cumulative error curve per method, pooled over
//                            poses, flip forgiven per vertex and per map), topkids.json (everything, with the
//                            per-method pooled summary). topkids.csv's columns and topkids.json's rows are
//                            TopkidsRow's fields by name (under_0.1 for under_0_1, 0/1 for the booleans in
//                            the CSV; torn_edges −1 for a method that does not tear), the summary's entries
//                            TopkidsSummary's, with its curves as fraction and whole_map_fraction
//   draw_topkids_figure      out/topkids.png from curves.csv and topkids.json (experiments/figures.h), its
//                            outcome recorded in the result and topkids.json
//   write_topkids_report     out/report.md (the table, the figure, how it was made) from the result and
//                            the options it was run with
//
// Cost: the forms (Coulomb a few seconds per 12,000-vertex pose; MDS an all-pairs geodesic matrix, n² floats:
// 576 MB at 12,000 vertices, and SMACOF's O(n²) iterations, minutes per pose); ICP ~0.1 s per pair; scoring
// one fast-marching run per distinct true or mirrored vertex (≤ 2 × samples) on the reference.
#pragma once

#include <functional>
#include <map>
#include <string>
#include <vector>

#include "cshapes/geodesics/geodesics.h"
#include "cshapes/support/progress.h"
#include "cshapes/matching/icp.h"
#include "cshapes/pipeline/canonical_form_methods.h"
#include "cshapes/pipeline/resampled_dataset.h"
#include "cshapes/pipeline/shape_failures.h"
#include "cshapes/support/figure_format.h"

namespace cshapes {

// A map is mirrored when its mean error against the mirrored truth is at most this fraction of its mean error
// against the truth (see above).
constexpr double kMirroredErrorRatio = 0.5;

// The experiment's own options, each declared once (support/option_declaration.h): `cshapes experiment
// topkids`'s flags and experiment_topkids()'s keywords.
namespace topkids_options {
inline const OptionDeclaration kReference{
    "reference", "--reference", "file stem of the reference pose, the null shape every pose is matched to"};
inline const OptionDeclaration kPoses{
    "poses", "--poses",
    "query poses, by file stem (comma-separated on the command line); default: every NAME_ref.txt but the "
    "reference's"};
inline const OptionDeclaration kSamples{
    "samples", "--samples",
    "ground-truth vertices scored per pose, evenly spaced over NAME_ref.txt (0: all)"};
inline const OptionDeclaration kData{"data", "--data",
    "folder with REFERENCE.off and, per query pose, NAME.off, NAME_ref.txt (NAME_sym.txt)"};
inline const OptionDeclaration kDraw =
    negated_option("draw", "--no-draw", "draw topkids.png (drawing needs Python with matplotlib)");
inline const std::vector<const OptionDeclaration*> kAll = {&kReference, &kPoses, &kSamples, &kDraw};
}  // namespace topkids_options

struct TopkidsExperimentOptions {
  std::string data;                 // the folder (see above)
  std::string out;                  // output folder; out/cache makes reruns resume
  // Write into `out` although it holds files cshapes did not write (support/output_folder.h); they stay.
  bool force = false;
  // Read manifest or .cla entries outside the dataset's folder (data/dataset.h: read_dataset).
  bool allow_outside = false;
  std::string reference = "kid00";  // file stem of the reference pose
  std::vector<std::string> poses;   // query poses by file stem; empty: every NAME_ref.txt but the reference's
  // Every registered method by default; empty: the inputs alone.
  std::vector<std::string> methods = canonical_form_methods();
  int samples = 1000;  // ground-truth vertices per pose, evenly spaced over NAME_ref.txt; ≤ 0: all
  // Method options (canon.method is set per method; MDS geodesics: canon.geodesics, heat by default).
  CanonicalFormOptions canon = experiment_canonical_form_options();
  IcpOptions icp;  // the retrieval's alignment (defaults: reflections allowed)
  // Geodesics on the reference for the errors: fast marching (stencils built once, ~1-2% relative error).
  GeodesicOptions scoring_geodesics = [] {
    GeodesicOptions g;
    g.method = GeodesicMethod::FastMarching;
    return g;
  }();
  // vertices > 0: the reference and the poses remeshed to about that many vertices first (see above); 0: as
  // they are.
  ResampleOptions resample;
  double max_threshold = 0.5;  // curves: thresholds 0 .. max_threshold (units of √area of the reference)
  int curve_points = 101;      // points of each curve
  // draw_topkids_figure draws out/topkids.png (experiments/plots/topkids_figure.py); false: it records
  // "not requested (--no-draw)" instead.
  bool figure = true;
  // The figure's format: png, pdf or svg (support/figure_format.h).
  FigureFormat figure_format = FigureFormat::png;
  ProgressFn progress;                           // stage "topkids" per pose
  std::function<void(const std::string&)> note;  // one line of progress text (repairs, timings)
};

// One method (or "inputs") on one query pose.
struct TopkidsRow {
  std::string pose;
  std::string method;        // "inputs", "coulomb", "cmds" or "smacof"
  int samples = 0;           // ground-truth vertices scored
  int unmapped = 0;          // of them, vertices with no image (dropped from the pose's form)
  int symmetric_chosen = 0;  // of them, errors measured to the mirrored truth (a forgiven flip)
  double mean_error = 0;     // over mapped samples, units of √area(reference)
  double median_error = 0;
  double under_0_1 = 0;   // fraction of samples with error ≤ 0.1
  double under_0_25 = 0;  // ≤ 0.25
  // The same with the flip forgiven for the whole map only (the better of truth and mirrored truth for all
  // samples together, eval/correspondence_error.h): stricter, a map mixing the sides is not forgiven.
  bool whole_map_mirrored = false;  // the mirrored truth was the better one (by any margin)
  double whole_map_mean_error = 0, whole_map_under_0_1 = 0, whole_map_under_0_25 = 0;
  // Mean error against the truth alone (no flip forgiven), and against the mirrored truth (the truth where a
  // vertex has no mirror: both the same without NAME_sym.txt), their ratio (NaN when both are 0); mirrored:
  // ratio ≤ kMirroredErrorRatio.
  double direct_mean_error = 0, mirrored_mean_error = 0, mirror_ratio = 0;
  bool mirrored = false;
  bool reflected = false;        // the ICP alignment is a reflection (det R = −1)
  double icp_rmse = 0;           // of the alignment, in the reference form's units
  double icp_rmse_relative = 0;  // over the reference form's bounding-box diagonal
  long torn_edges = -1;          // coulomb: edges of the pose's form torn; −1 for other methods
  std::string repair;            // what the method's repair did to the pose ("" when nothing)
};

struct TopkidsSummary {  // one method, pooled over poses
  std::string method;
  int samples = 0;
  double mean_error = 0, median_error = 0, under_0_1 = 0, under_0_25 = 0;
  Eigen::VectorXd fraction;  // cumulative curve at TopkidsExperimentResult::thresholds
  // Flip forgiven per map (TopkidsRow::whole_map_*), pooled likewise.
  double whole_map_mean_error = 0, whole_map_under_0_1 = 0, whole_map_under_0_25 = 0;
  Eigen::VectorXd whole_map_fraction;
  // Per pose instead of pooled: the median over poses of the pose's mean error (flip forgiven per vertex), of
  // its mean error against the truth alone, and the poses whose map is mirrored (TopkidsRow::mirrored).
  int poses = 0, mirrored_poses = 0;
  double median_pose_mean_error = 0, median_pose_direct_error = 0;
};

// With resampling: one pose's ground-truth vertices carried to its remesh (pipeline/remesh_samples.h).
struct TopkidsCarriedRow {
  std::string pose;
  int vertices = 0;          // ground-truth vertices of the pose, each carried once
  double mean_distance = 0;  // mean ‖vertex − located point‖ / the pose input's bounding-box diagonal
  double max_distance = 0;   // the largest, likewise
  int relocated = 0;         // closest to another part, located on their own (pipeline/remesh_samples.h)
  int off_part = 0;          // closest to another part, no triangle of their own within reach
};

struct TopkidsExperimentResult {
  std::vector<std::string> poses;
  std::vector<std::string> methods;  // "inputs" first, then the options' methods
  std::vector<TopkidsRow> rows;      // per pose, per method in `methods` order
  Eigen::VectorXd thresholds;
  std::vector<TopkidsSummary> summaries;                // per method in `methods` order
  std::map<std::string, std::string> reference_repair;  // per method: what its repair did to the reference
  std::string scoring_repair;  // the repair of the reference for the scoring geodesics ("" when none)
  double reference_sqrt_area = 0;
  std::string figure;          // "topkids.png" (.pdf, .svg) when draw_topkids_figure drew it, else ""
  std::string figure_problem;  // why it was not drawn (set by draw_topkids_figure)
  long forms_computed = 0, forms_cached = 0, scorings_computed = 0, scorings_cached = 0;
  double seconds = 0;
  // Query poses whose canonical form failed by some method, left out (not in `poses`); geodesic fallbacks,
  // shapes --resample kept at their own resolution and poses (the reference among them) of the same bytes as
  // another (each kept): pipeline/shape_failures.h. The reference's failure ends the run.
  std::vector<ShapeFailure> failures;
  bool resampled = false;                  // options.resample.vertices > 0
  ResampledDataset resampling;             // when resampled: the remeshes and their measures
  std::vector<TopkidsCarriedRow> carried;  // when resampled: per pose (the poses read, left out or not)
  // When resampled: the largest distance from a vertex of the reference's remesh to the reference input's
  // vertex it goes back to, over the input's bounding-box diagonal.
  double reference_back_distance = 0;
};

// The query poses of a folder: every NAME_ref.txt whose NAME is not the reference, in name order. Throws when
// the folder is missing or holds none.
std::vector<std::string> topkids_poses(const std::string& data, const std::string& reference);

// The mesh file of a pose: NAME.off (.ply .obj .stl .vert) in data; throws naming what was looked for.
std::string topkids_mesh_path(const std::string& data, const std::string& name);

// The measurement (see above): reads every input first (a missing or malformed file stops the run before any
// work), computes or reads from out/cache the forms and scorings, and writes topkids.csv, curves.csv and
// topkids.json into options.out. No figure, no report.md. Throws when the reference's form fails or every
// pose is left out.
TopkidsExperimentResult run_topkids_experiment(const TopkidsExperimentOptions& options);

// Draws options.out/topkids.png from the data files run_topkids_experiment wrote, when options.figure, and
// records the outcome (result.figure, result.figure_problem) in the result and in topkids.json. A figure that
// cannot be drawn is not an error: figure_problem says why.
void draw_topkids_figure(TopkidsExperimentResult& result, const TopkidsExperimentOptions& options);

// Writes folder/report.md from the result and the options it was run with (data, reference, samples, ICP and
// scoring options, methods): the pooled table, the figure (or why there is none), the per-pose table, the
// shapes left out, repairs and tearing, the command that reproduces it. "—" for a value not measured.
void write_topkids_report(const TopkidsExperimentResult& result, const TopkidsExperimentOptions& options,
                          const std::string& folder);

// The experiment as `cshapes experiment topkids` runs it: run_topkids_experiment, draw_topkids_figure,
// write_topkids_report into options.out.
TopkidsExperimentResult topkids_experiment(const TopkidsExperimentOptions& options);

}  // namespace cshapes
