#include "cshapes/experiments/noise_experiment.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <limits>
#include <map>
#include <nlohmann/json.hpp>
#include <optional>
#include <set>
#include <sstream>

#include "cshapes/support/atomic_file.h"
#include "cshapes/data/dataset.h"
#include "cshapes/support/error.h"
#include "cshapes/mesh/io.h"
#include "cshapes/mesh/rigid_transform.h"
#include "cshapes/support/timing.h"
#include "cshapes/support/output_folder.h"
#include "cshapes/data/topological_noise.h"
#include "cshapes/data/cache.h"
#include "cshapes/eval/pairwise_distances.h"
#include "cshapes/eval/retrieval.h"
#include "cshapes/experiments/figures.h"
#include "cshapes/experiments/outside_methods_report.h"
#include "cshapes/pipeline/outside_methods.h"
#include "cshapes/experiments/paper_report.h"
#include "cshapes/matching/shape_distance.h"
#include "cshapes/pipeline/experiment_kit.h"
#include "cshapes/pipeline/glued_meshes.h"
#include "cshapes/pipeline/shape_failures.h"

namespace cshapes {

namespace fs = std::filesystem;
using nlohmann::json;

namespace {

const char* const kDistanceKinds[] = {"hausdorff", "chamfer", "rmse"};

// A clean pose and its versions.
struct Pose {
  std::string name, class_name, path;
  Mesh mesh;
  long chi = 0;
};

// One shape to canonize: a clean pose (level 0) or one of its glued versions.
struct Variant {
  int pose = 0;
  int level = 0;
  std::string name;  // the pose's name, or NAME_glueK
  Mesh mesh;
  std::vector<int> glued;  // vertices of glued pairs
};

// The glued version of a pose at one level, through the glued-mesh cache every experiment shares (failures
// are cached too, so a rerun glues nothing). Fills `glue` (seed, χ check, error); returns the mesh when it
// can be used.
std::optional<Mesh> glue_pose(const Pose& pose, int level, const NoiseExperimentOptions& o,
                              const DiskCache& cache, NoiseGlue& glue, std::vector<int>& glued,
                              NoiseExperimentResult& result) {
  TopologicalNoiseOptions no;
  no.glue_count = level;
  no.seed = glue.seed;
  no.relax_steps = o.relax_steps;
  GluedMesh g = cached_glued_mesh(cache, pose.mesh, no);
  ++(g.cached ? result.glued_cached : result.glued_computed);
  glue.chi_before = pose.chi;
  glue.chi_expected = pose.chi - 2L * level;
  if (!g.ok()) {
    glue.ok = false;
    glue.error = "glue failed: " + g.error;
    ++result.glue_failures;
    return std::nullopt;
  }
  glued = std::move(g.glued);
  glue.relax_steps_used = g.relax_steps_used;
  glue.chi_after = mesh_info(g.mesh).euler_characteristic;
  if (glue.chi_after != glue.chi_expected) {
    glue.ok = false;
    glue.error =
        detail::concat("Euler characteristic ", glue.chi_after, " after ", level, " glues, expected ",
                       glue.chi_expected, " (", glue.chi_before, " − 2·", level, ")");
    ++result.chi_mismatches;
    return std::nullopt;
  }
  return std::move(g.mesh);
}

// Clean poses per class, in the data's order; a file that cannot be read is skipped with its reason.
std::vector<Pose> select_poses(const NoiseExperimentOptions& o, std::vector<std::string>& skipped,
                               std::vector<ShapeFailure>& failures) {
  const Dataset data = read_dataset(o.data, o.allow_outside);
  // The folder's entries that are no shape (a loop of links, a FIFO, a second file of one name): left out.
  add_records(failures, left_out_records(data.left_out, o.canon.strict), o.note);
  std::vector<Pose> poses;
  for (const std::string& cls : data.classes) {
    int taken = 0;
    for (const DatasetEntry& e : data.entries) {
      if (e.class_name != cls || e.noisy) continue;
      if (o.poses_per_class > 0 && taken >= o.poses_per_class) break;
      Pose p;
      p.name = e.name;
      p.class_name = cls;
      p.path = e.path;
      try {
        p.mesh = read_mesh(e.path);
        CSHAPES_REQUIRE(p.mesh.num_faces() > 0, e.path, ": a point cloud (gluing needs faces)");
      } catch (const WriteError&) {
        throw;  // the run's own files: never one shape's failure
      } catch (const Error& error) {
        if (o.canon.strict) throw;
        say(o.note, std::string("skipped: ") + error.what());
        skipped.push_back(error.what());
        failures.push_back(read_failure(e.name, e.path, error));
        continue;
      }
      p.chi = mesh_info(p.mesh).euler_characteristic;
      poses.push_back(std::move(p));
      ++taken;
    }
  }
  CSHAPES_REQUIRE(!poses.empty(), o.data, ": no clean pose could be read");
  return poses;
}

}  // namespace

std::uint64_t glue_seed(std::uint64_t seed, const std::string& shape, int level) {
  const std::string hex =
      sha256_hex(cache_key({"noise-glue", std::to_string(seed), shape, std::to_string(level)}));
  return std::stoull(hex.substr(0, 16), nullptr, 16);
}

namespace {

// What the steps of a run share: the options (levels sorted), the poses and their glued versions, the forms.
struct NoiseRun {
  explicit NoiseRun(const NoiseExperimentOptions& options)
      : o(options),
        folder(options.out),
        form_cache(folder.cache("forms")),
        misc_cache(folder.cache("misc")) {}
  const NoiseExperimentOptions& o;
  ExperimentFolder folder;
  DiskCache form_cache, misc_cache;
  std::vector<Pose> poses;
  std::vector<Variant> variants;                     // clean poses first (index = pose), then glued versions
  std::map<std::pair<int, int>, int> variant_of;     // (pose, level) -> index in variants, when usable
  std::map<std::string, std::vector<Points>> forms;  // per method, per variant
  std::map<std::string, std::vector<std::string>> form_keys;  // per method, per variant: cache keys
  NoiseExperimentResult result;
};

// 1. Every pose at every level: the clean pose (level 0) and its glued versions (χ checked), their meshes
// written to out/shapes.
void glue_every_pose(NoiseRun& run) {
  const NoiseExperimentOptions& o = run.o;
  const std::vector<int>& levels = o.levels;
  NoiseExperimentResult& result = run.result;
  std::vector<Pose>& poses = run.poses;
  std::vector<Variant>& variants = run.variants;
  std::map<std::pair<int, int>, int>& variant_of = run.variant_of;
  const DiskCache& misc_cache = run.misc_cache;
  for (size_t p = 0; p < poses.size(); ++p) {
    variants.push_back({static_cast<int>(p), 0, poses[p].name, poses[p].mesh, {}});
    if (levels.front() == 0) variant_of[{static_cast<int>(p), 0}] = static_cast<int>(p);
  }
  say(o.note, "== gluing " + std::to_string(poses.size()) + " poses");
  for (size_t p = 0; p < poses.size(); ++p)
    for (int level : levels) {
      if (level == 0) continue;
      NoiseGlue g;
      g.shape = poses[p].name;
      g.class_name = poses[p].class_name;
      g.level = level;
      g.seed = glue_seed(o.seed, poses[p].name, level);
      std::vector<int> glued;
      std::optional<Mesh> m = glue_pose(poses[p], level, o, misc_cache, g, glued, result);
      if (!g.ok) say(o.note, "  " + g.shape + " at " + std::to_string(level) + " glues left out: " + g.error);
      result.glues.push_back(g);
      if (!m) continue;
      Variant v{static_cast<int>(p), level, poses[p].name + "_glue" + std::to_string(level), std::move(*m),
                std::move(glued)};
      write_mesh(run.folder.path("shapes/" + v.name + ".off"), v.mesh);
      variant_of[{static_cast<int>(p), level}] = static_cast<int>(variants.size());
      variants.push_back(std::move(v));
    }
}

// 2. Canonical forms of every variant by every method (cached); MDS methods share one geodesic matrix. A
// variant whose form fails by any method is left out; a clean pose's failure leaves out the pose with every
// glued version of it (pipeline/shape_failures.h).
void canonize_every_variant(NoiseRun& run) {
  const NoiseExperimentOptions& o = run.o;
  const std::vector<int>& levels = o.levels;
  NoiseExperimentResult& result = run.result;
  std::vector<Pose>& poses = run.poses;
  std::vector<Variant>& variants = run.variants;
  std::map<std::pair<int, int>, int>& variant_of = run.variant_of;
  std::map<std::string, std::vector<Points>>& forms = run.forms;
  std::map<std::string, std::vector<std::string>>& form_keys = run.form_keys;
  const DiskCache& form_cache = run.form_cache;
  say(o.note, "== canonical forms (" + std::to_string(variants.size()) + " shapes × " +
                  std::to_string(o.methods.size()) + " methods)");
  std::vector<char> failed(variants.size(), 0);
  auto path_of = [&](const Variant& v) {
    return v.level == 0 ? poses[static_cast<size_t>(v.pose)].path : run.folder.path("shapes/" + v.name + ".off");
  };
  std::vector<ShapeAhead> ahead;
  for (const Variant& v : variants) ahead.push_back({&v.mesh, path_of(v)});
  run_commands_ahead(form_cache, ahead, o.canon, o.methods);
  for (size_t i = 0; i < variants.size(); ++i) {
    const Variant& v = variants[i];
    const size_t failures_before = result.failures.size();
    const std::string path = path_of(v);
    std::optional<std::vector<CachedForm>> computed = shape_canonical_forms(
        form_cache, v.mesh, options_per_method(o.canon, o.methods, path), v.name, result.failures);
    for (size_t k = failures_before; k < result.failures.size(); ++k)
      say(o.note, "  " + describe(result.failures[k]));
    failed[i] = !computed;
    for (size_t k = 0; k < o.methods.size(); ++k) {
      if (computed)
        (*computed)[k].cached ? ++result.canonical_forms_cached : ++result.canonical_forms_computed;
      forms[o.methods[k]].push_back(computed ? std::move((*computed)[k].form.X) : Points());
      form_keys[o.methods[k]].push_back(computed ? (*computed)[k].key : std::string());
    }
    if (o.progress)
      o.progress("canonical forms", static_cast<double>(i + 1), static_cast<double>(variants.size()));
  }
  // A form too far in size from the method's others for ICP to align at one scale: its shape is left out.
  for (const std::string& m : o.methods) {
    std::vector<const Points*> pointers;
    for (size_t i = 0; i < variants.size(); ++i) pointers.push_back(failed[i] ? nullptr : &forms[m][i]);
    for (size_t i : forms_of_incomparable_size(pointers)) {
      if (o.canon.strict) fail(variants[i].name, ": ", incomparable_size_reason());
      failed[i] = 1;
      result.failures.push_back({variants[i].name, "", m, "alignment", incomparable_size_reason(), ""});
      say(o.note, "  " + describe(result.failures.back()));
    }
  }
  if (std::find(failed.begin(), failed.end(), 1) != failed.end()) {
    // Renumber: poses whose clean form failed go, with their variants; then variants whose form failed.
    std::vector<int> new_pose(poses.size(), -1);
    std::vector<Pose> kept_poses;
    for (size_t p = 0; p < poses.size(); ++p)
      if (!failed[p]) {
        new_pose[p] = static_cast<int>(kept_poses.size());
        kept_poses.push_back(std::move(poses[p]));
      } else {
        for (const Variant& v : variants)
          if (v.pose == static_cast<int>(p) && v.level > 0)
            say(o.note, "  " + v.name + " left out with its clean pose");
      }
    std::vector<Variant> kept;
    std::map<std::string, std::vector<Points>> kept_forms;
    std::map<std::string, std::vector<std::string>> kept_keys;
    variant_of.clear();
    // In order: the clean poses kept come first, so a clean variant's index is still its pose's.
    for (size_t i = 0; i < variants.size(); ++i) {
      Variant& v = variants[i];
      if (failed[i] || new_pose[static_cast<size_t>(v.pose)] < 0) continue;
      v.pose = new_pose[static_cast<size_t>(v.pose)];
      if (v.level > 0 || levels.front() == 0) variant_of[{v.pose, v.level}] = static_cast<int>(kept.size());
      for (const std::string& m : o.methods) {
        kept_forms[m].push_back(std::move(forms[m][i]));
        kept_keys[m].push_back(std::move(form_keys[m][i]));
      }
      kept.push_back(std::move(v));
    }
    poses = std::move(kept_poses);
    variants = std::move(kept);
    forms = std::move(kept_forms);
    form_keys = std::move(kept_keys);
  }
}

// b) Method m's noisy form against its own clean pose's form, per pose measured at `level` (RMS after the best
// rigid fit, over the clean form's diagonal); by pose name into *by_pose.
std::vector<double> level_form_rms(NoiseRun& run, const std::string& m, int level, json* by_pose) {
  std::vector<double> rms;
  for (size_t p = 0; p < run.poses.size(); ++p) {
    auto it = run.variant_of.find({static_cast<int>(p), level});
    if (it == run.variant_of.end()) continue;
    const Points& clean = run.forms[m][p];
    const double value = aligned_rms(run.forms[m][static_cast<size_t>(it->second)], clean, true) /
                         bbox_diagonal(finite_rows(clean));
    rms.push_back(value);
    (*by_pose)[run.poses[p].name] = value;
  }
  return rms;
}

// a) The retrieval row of method m at `level` under one distance (matrix M): each query (a variant) among the
// clean poses but its own; the queries' average precisions into *queries. clean_ap holds level 0's per
// (distance, pose), filled when level is 0, the baseline of the same poses.
NoiseRow retrieval_row(NoiseRun& run, const std::string& m, int level, const char* kind,
                       const Eigen::MatrixXd& M, std::map<std::pair<std::string, size_t>, double>& clean_ap,
                       json* queries) {
  const std::vector<Pose>& poses = run.poses;
  NoiseRow row;
  row.method = m;
  row.level = level;
  row.distance = kind;
  for (size_t p = 0; p < poses.size(); ++p) {
    auto it = run.variant_of.find({static_cast<int>(p), level});
    if (it == run.variant_of.end()) continue;
    std::vector<double> distances;
    std::vector<char> relevant;
    for (size_t c = 0; c < poses.size(); ++c) {
      if (c == p) continue;
      distances.push_back(M(it->second, static_cast<Index>(c)));
      relevant.push_back(poses[c].class_name == poses[p].class_name);
    }
    double nn = 0;  // 1 or 0, a share when the nearest are tied
    const double ap = average_precision(distances, relevant, &nn);
    if (ap < 0) continue;  // the only pose of its class: nothing to retrieve
    if (level == 0) clean_ap[{kind, p}] = ap;
    row.map += ap;
    row.nn += nn;
    ++row.queries;
    if (clean_ap.count({kind, p})) {
      row.map_clean_same_poses = std::isnan(row.map_clean_same_poses) ? 0 : row.map_clean_same_poses;
      row.map_clean_same_poses += clean_ap.at({kind, p});
    }
    queries->push_back({{"query", run.variants[static_cast<size_t>(it->second)].name}, {"ap", ap}, {"nn", nn}});
  }
  if (row.queries > 0) {
    row.map /= row.queries;
    row.nn /= row.queries;
    row.map_clean_same_poses /= row.queries;  // NaN without level 0
  } else {  // no pose could be glued this often (or no class has two poses): nothing measured
    row.map = row.nn = std::numeric_limits<double>::quiet_NaN();
  }
  return row;
}

// Method m: the ICP distances of `pairs` (queries against clean poses), the pose variation, and per level the
// form distances and the retrieval rows under each distance.
void measure_method(NoiseRun& run, const std::string& m, const std::vector<std::pair<int, int>>& pairs) {
  const NoiseExperimentOptions& o = run.o;
  NoiseExperimentResult& result = run.result;
  const std::vector<Pose>& poses = run.poses;
  say(o.note, "== ICP distances, " + method_title(m));
  PairwiseDistanceOptions po;
  po.cache_dir = run.folder.cache_directory("pairs");
  po.progress = renamed_stage(o.progress, "distances, " + method_title(m));
  po.only_pairs = pairs;
  PairwiseDistanceResult pd =
      pairs.empty() ? PairwiseDistanceResult{} : pairwise_distances(run.forms[m], run.form_keys[m], po);
  result.pairs_computed += pd.computed;
  result.pairs_cached += pd.cached;
  const std::map<std::string, const Eigen::MatrixXd*> matrices = {
      {"hausdorff", &pd.hausdorff}, {"chamfer", &pd.chamfer}, {"rmse", &pd.rmse}};

  // Pose variation for scale: clean poses of one class (level-0 pairs, when level 0 ran).
  std::vector<double> within;
  if (o.levels.front() == 0)
    for (size_t a = 0; a < poses.size(); ++a)
      for (size_t b = a + 1; b < poses.size(); ++b)
        if (poses[a].class_name == poses[b].class_name)
          within.push_back(pd.rmse(static_cast<Index>(a), static_cast<Index>(b)) /
                           bbox_diagonal(finite_rows(run.forms[m][b])));
  if (!within.empty()) result.pose_variation[m] = median(within);

  std::map<std::pair<std::string, size_t>, double> clean_ap;
  for (int level : o.levels) {
    json rms_by_pose = json::object();
    const std::vector<double> rms = level_form_rms(run, m, level, &rms_by_pose);
    result.form_rms[m][std::to_string(level)] = rms_by_pose;
    double rms_mean = 0;
    for (double x : rms) rms_mean += x;
    rms_mean =
        rms.empty() ? std::numeric_limits<double>::quiet_NaN() : rms_mean / static_cast<double>(rms.size());
    for (const char* kind : kDistanceKinds) {
      json queries = json::array();
      NoiseRow row = retrieval_row(run, m, level, kind, *matrices.at(kind), clean_ap, &queries);
      row.form_rms_median = rms.empty() ? std::numeric_limits<double>::quiet_NaN() : median(rms);
      row.form_rms_mean = rms_mean;
      row.form_poses = static_cast<int>(rms.size());
      result.per_query[m][std::to_string(level)][kind] = queries;
      result.rows.push_back(row);
    }
  }
}

// 3. ICP distances (every query, a variant, against every clean pose but its own), then per method and level
// the retrieval rows and the form distances.
void measure(NoiseRun& run) {
  std::vector<std::pair<int, int>> pairs;
  for (const auto& [pose_level, q] : run.variant_of)
    for (size_t c = 0; c < run.poses.size(); ++c)
      if (static_cast<int>(c) != pose_level.first) pairs.emplace_back(q, static_cast<int>(c));
  for (const std::string& m : run.o.methods) measure_method(run, m, pairs);
}

}  // namespace

NoiseExperimentResult run_noise_experiment(const NoiseExperimentOptions& options) {
  const auto start = WallClock::now();
  CSHAPES_REQUIRE(!options.out.empty(), "experiment noise: --out is required");
  CSHAPES_REQUIRE(!options.methods.empty(), "experiment noise: no method given");
  require_canonical_form_methods(options.methods, "experiment noise");
  NoiseExperimentOptions o = options;
  std::sort(o.levels.begin(), o.levels.end());
  CSHAPES_REQUIRE(!o.levels.empty() && o.levels.front() >= 0, "experiment noise: levels must be ≥ 0");
  CSHAPES_REQUIRE(std::adjacent_find(o.levels.begin(), o.levels.end()) == o.levels.end(),
                  "experiment noise: a level is given twice");
  // --resample: the run reads the remeshed collection; the report names the data given.
  ResampledDataset resampled;
  if (o.resample.vertices > 0) {
    resampled = resample_dataset(o.data, o.resample, ExperimentFolder(o.out).path("resampled"),
                                 ExperimentFolder(o.out).cache("remeshed"), nullptr, o.note, o.allow_outside);
    o.data = resampled.data;
    o.allow_outside = true;  // the remeshed collection's manifest lists kept shapes by their own paths
  }
  NoiseRun run(o);
  NoiseExperimentResult& result = run.result;
  result.options = o;
  result.options.data = options.data;
  result.resampled = o.resample.vertices > 0;
  result.resampling = resampled;
  result.options.progress = {};
  result.options.note = {};

  // A shape --resample kept at its own resolution, and two poses of the same bytes under different names
  // (both stay queries): said on stderr, in report.md and in the JSON.
  add_records(result.failures, resample_records(resampled), o.note);
  say(o.note, "== poses from " + o.data);
  run.poses = select_poses(o, result.skipped, result.failures);
  std::vector<DatasetEntry> chosen;
  for (const Pose& p : run.poses) chosen.push_back({p.path, p.name, p.class_name, -1, false});
  add_records(result.failures, same_content_records(chosen), o.note);
  glue_every_pose(run);
  canonize_every_variant(run);
  result.poses = static_cast<int>(run.poses.size());
  for (const Pose& p : run.poses)
    result.pose_list.push_back({p.name, p.class_name, p.path, p.mesh.num_vertices(), p.chi});
  {
    std::set<std::string> classes;
    for (const Pose& p : run.poses) classes.insert(p.class_name);
    result.classes = static_cast<int>(classes.size());
  }
  CSHAPES_REQUIRE(!run.poses.empty(), o.data, ": every clean pose was left out (see above)");

  measure(run);
  result.seconds = seconds_since(start);
  return std::move(result);
}

NoiseExperimentResult noise_experiment(const NoiseExperimentOptions& o) {
  const auto start = WallClock::now();
  OutputRun output(o.out, "experiment noise", experiment_kept_folders(), o.force);
  start_outside_methods(o.out);
  NoiseExperimentResult result = run_noise_experiment(o);
  write_noise_outputs(result, o.out);
  if (!o.figure) {
    result.figure_note = "not requested (`--no-draw`).";
  } else {
    const FigureRun drawn =
        draw_figure("noise_figure.py", {o.out}, (fs::path(o.out) / "noise").string(), o.figure_format,
                    o.methods);
    result.figure = drawn.drawn;
    result.figure_note = drawn.problem.empty() ? "" : drawn.problem + ".";
  }
  if (!result.figure) say(o.note, "no figure: " + result.figure_note);
  result.seconds = seconds_since(start);
  write_noise_report(result, o.out);
  finish_outside_methods(o.methods, o.out, o.note);
  output.commit();
  return result;
}

}  // namespace cshapes
