#include "cshapes/experiments/topkids_experiment.h"
#include "cshapes/experiments/topkids_experiment_detail.h"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <limits>
#include <map>
#include <nlohmann/json.hpp>
#include <optional>
#include <set>
#include <sstream>

#include "cshapes/data/dataset.h"
#include "cshapes/support/error.h"
#include "cshapes/mesh/io.h"
#include "cshapes/support/option_limits.h"
#include "cshapes/support/timing.h"
#include "cshapes/support/output_folder.h"
#include "cshapes/data/cache.h"
#include "cshapes/eval/correspondence_error.h"
#include "cshapes/experiments/figures.h"
#include "cshapes/experiments/outside_methods_report.h"
#include "cshapes/pipeline/outside_methods.h"
#include "cshapes/matching/nearest_neighbors.h"
#include "cshapes/pipeline/experiment_kit.h"
#include "cshapes/pipeline/remesh_samples.h"
#include "cshapes/pipeline/shape_failures.h"

namespace cshapes {

namespace fs = std::filesystem;
using nlohmann::json;
using topkids_detail::kInputs;

namespace {

const std::vector<std::string> kMeshExtensions = {"off", "ply", "obj", "stl", "vert"};

// ---- Point maps -------------------------------------------------------------------------------------------

// A map from every vertex of a source point set to the nearest vertex of a target set after ICP, over the
// finite rows of each (a canonical form has NaN rows where its repair dropped a vertex: those get −1).
struct PointMap {
  Eigen::VectorXi map;  // per source row: target row, or −1
  bool reflected = false;
  double rmse = 0;
};

std::vector<int> finite_rows(const Points& X) {
  std::vector<int> rows;
  for (Index i = 0; i < X.rows(); ++i)
    if (X.row(i).allFinite()) rows.push_back(static_cast<int>(i));
  return rows;
}

Points take_rows(const Points& X, const std::vector<int>& rows) {
  Points Y(static_cast<Index>(rows.size()), 3);
  for (size_t k = 0; k < rows.size(); ++k) Y.row(static_cast<Index>(k)) = X.row(rows[k]);
  return Y;
}

PointMap align_and_map(const Points& source, const Points& target, const IcpOptions& options) {
  const std::vector<int> s_rows = finite_rows(source), t_rows = finite_rows(target);
  IcpResult r = icp(take_rows(source, s_rows), take_rows(target, t_rows), options);
  PointMap pm;
  pm.map = Eigen::VectorXi::Constant(source.rows(), -1);
  for (size_t k = 0; k < s_rows.size(); ++k)
    pm.map[s_rows[k]] = t_rows[static_cast<size_t>(r.source_to_target[static_cast<Index>(k)])];
  pm.reflected = r.transform.is_reflection();
  pm.rmse = r.rmse;
  return pm;
}

// With resampling: ICP between the two forms (each on its remesh), then each carried vertex of the source
// input (its form position interpolated on the source's remesh, moved by the alignment) to the nearest
// finite row of the target form, taken back to a vertex of the target input by `back` (per target row).
// The map has a row per vertex of the source input (−1 where no carried vertex is, or its form is not
// finite there).
PointMap align_and_map_carried(const Points& source, const Faces& source_faces, const RemeshSamples& carried,
                               Index source_input_vertices, const Points& target, const Eigen::VectorXi& back,
                               const IcpOptions& options) {
  const std::vector<int> s_rows = finite_rows(source), t_rows = finite_rows(target);
  const Points aligned_target = take_rows(target, t_rows);
  const IcpResult r = icp(take_rows(source, s_rows), aligned_target, options);
  const NearestNeighbors nearest(aligned_target);
  const Eigen::MatrixXd at = interpolate_on_surface(source_faces, carried.at, source);
  PointMap pm;
  pm.map = Eigen::VectorXi::Constant(source_input_vertices, -1);
  for (size_t k = 0; k < carried.vertices.size(); ++k) {
    const Eigen::Vector3d x = at.row(static_cast<Index>(k)).transpose();
    if (!x.allFinite()) continue;
    pm.map[carried.vertices[k]] = back[t_rows[static_cast<size_t>(nearest.nearest(r.transform.apply(x)))]];
  }
  pm.reflected = r.transform.is_reflection();
  pm.rmse = r.rmse;
  return pm;
}

// Errors in a cache entry: JSON has no infinity, so an unmapped sample is stored as −1.
json errors_to_json(const Eigen::VectorXd& e) {
  std::vector<double> v(static_cast<size_t>(e.size()));
  for (Index i = 0; i < e.size(); ++i) v[static_cast<size_t>(i)] = std::isfinite(e[i]) ? e[i] : -1.0;
  return v;
}
Eigen::VectorXd errors_from_json(const json& j) {
  std::vector<double> v = j.get<std::vector<double>>();
  Eigen::VectorXd e(static_cast<Index>(v.size()));
  for (size_t i = 0; i < v.size(); ++i)
    e[static_cast<Index>(i)] = v[i] < 0 ? std::numeric_limits<double>::infinity() : v[i];
  return e;
}

// ---- Inputs -----------------------------------------------------------------------------------------------

struct Pose {
  std::string name;
  std::string mesh_path, ref_path, sym_path;  // sym_path "" when there is none
  Mesh mesh;
  // The mesh the forms and ICP are computed on: the input, or with resampling its remesh; and its file.
  Mesh measured;
  std::string measured_path;
  RemeshSamples carried;  // with resampling: the ground-truth vertices on `measured`
};

// Everything the run reads, read and checked before any work.
struct TopkidsInputs {
  std::string reference_path;
  Mesh reference;
  Mesh reference_measured;  // as Pose::measured
  std::string reference_measured_path;
  Eigen::VectorXi reference_back;  // with resampling: per vertex of reference_measured, the input's nearest
  std::vector<Pose> poses;
};

void check_options(const TopkidsExperimentOptions& o) {
  require_canonical_form_methods(o.methods, "experiment topkids");
  check_distinct(o.poses, "experiment topkids: poses");
  CSHAPES_REQUIRE(o.max_threshold > 0.25 && o.curve_points >= 2,
                  "experiment topkids: the curve must reach past 0.25 with at least 2 points");
}

Pose read_pose(const TopkidsExperimentOptions& o, const std::string& name, const Mesh& reference) {
  CSHAPES_REQUIRE(name != o.reference, "experiment topkids: pose ", name, " is the reference");
  Pose p;
  p.name = name;
  p.ref_path = (fs::path(o.data) / (name + "_ref.txt")).string();
  CSHAPES_REQUIRE(fs::is_regular_file(p.ref_path), p.ref_path, ": not found (pose ", name,
                  " needs its ground truth)");
  p.mesh_path = topkids_mesh_path(o.data, name);
  const std::string sym = (fs::path(o.data) / (name + "_sym.txt")).string();
  if (fs::is_regular_file(sym)) p.sym_path = sym;
  p.mesh = read_mesh(p.mesh_path);
  p.measured = p.mesh;
  p.measured_path = p.mesh_path;
  // Checked now (the scoring reads them again, from its cache or not).
  read_correspondence_pairs(p.ref_path, p.mesh.num_vertices(), reference.num_vertices());
  if (!p.sym_path.empty())  // both columns are vertices of the pose (see mirrored_truth)
    read_correspondence_pairs(p.sym_path, p.mesh.num_vertices(), p.mesh.num_vertices());
  else
    say(o.note, p.name + ": no " + name + "_sym.txt: symmetric flips are not forgiven for this pose");
  return p;
}

TopkidsInputs read_inputs(const TopkidsExperimentOptions& o, const std::vector<std::string>& poses) {
  TopkidsInputs in;
  in.reference_path = topkids_mesh_path(o.data, o.reference);
  in.reference = read_mesh(in.reference_path);
  in.reference_measured = in.reference;
  in.reference_measured_path = in.reference_path;
  for (const std::string& name : poses) in.poses.push_back(read_pose(o, name, in.reference));
  return in;
}

// With resampling: the reference and the poses remeshed (cached), each one's measured mesh its remesh; the
// poses' ground-truth vertices carried there, the reference's remesh vertices taken back to its input.
void resample_inputs(const TopkidsExperimentOptions& o, const ExperimentFolder& folder, TopkidsInputs& in,
                     TopkidsExperimentResult& r) {
  Dataset d;
  d.source = o.data;
  d.entries.push_back({in.reference_path, o.reference, "kid", 0, false});
  for (size_t i = 0; i < in.poses.size(); ++i)
    d.entries.push_back({in.poses[i].mesh_path, in.poses[i].name, "kid", static_cast<int>(i) + 1, false});
  r.resampled = true;
  r.resampling =
      resample_dataset(d, o.resample, folder.path("resampled"), folder.cache("remeshed"), nullptr, o.note);
  std::map<std::string, const ResampledShape*> remesh_of;
  for (const ResampledShape& s : r.resampling.shapes) remesh_of[s.name] = &s;
  // The remesh of a shape (its input when it was kept at its own resolution).
  auto measured = [&](const std::string& name, Mesh& mesh, std::string& path) {
    const auto found = remesh_of.find(name);
    CSHAPES_REQUIRE(found != remesh_of.end(), "experiment topkids: ", name, " was not resampled");
    if (!found->second->remeshed) return;
    path = found->second->file;
    mesh = read_mesh(path);
  };
  measured(o.reference, in.reference_measured, in.reference_measured_path);
  Eigen::VectorXd squared;
  NearestNeighbors(in.reference.V).nearest_all(in.reference_measured.V, in.reference_back, squared);
  r.reference_back_distance = std::sqrt(squared.maxCoeff()) / finite_bbox_diagonal(in.reference.V);
  for (Pose& p : in.poses) {
    measured(p.name, p.measured, p.measured_path);
    const CorrespondencePairs truth =
        read_correspondence_pairs(p.ref_path, p.mesh.num_vertices(), in.reference.num_vertices());
    std::vector<int> vertices = truth.from;
    std::sort(vertices.begin(), vertices.end());
    vertices.erase(std::unique(vertices.begin(), vertices.end()), vertices.end());
    p.carried = carry_to_remesh(p.mesh, p.measured, vertices);
    TopkidsCarriedRow row;
    row.pose = p.name;
    row.vertices = static_cast<int>(vertices.size());
    row.mean_distance = p.carried.mean_distance;
    row.max_distance = p.carried.max_distance;
    row.relocated = p.carried.relocated;
    row.off_part = p.carried.off_part;
    r.carried.push_back(row);
    say(o.note, detail::concat("  ", p.name, ": ", row.vertices,
                               " ground-truth vertices carried to the remesh, ", carried_summary(p.carried)));
  }
}

// ---- Canonical forms --------------------------------------------------------------------------------------

// One shape's canonical forms by every method of the run, and their cache keys.
struct MethodForms {
  std::map<std::string, CanonicalForm> forms;
  std::map<std::string, std::string> keys;
};

// The forms of one shape (the two MDS methods share one geodesic matrix), counted in r and said in a note
// each. nullopt when the shape's form failed by some method: it is left out (pipeline/shape_failures.h), its
// record appended to r.failures.
std::optional<MethodForms> forms_of(const Mesh& mesh, const std::string& path, const DiskCache& form_cache,
                                    const TopkidsExperimentOptions& o, TopkidsExperimentResult& r) {
  const std::string name = fs::path(path).stem().string();
  const size_t failures_before = r.failures.size();
  std::optional<std::vector<CachedForm>> computed =
      shape_canonical_forms(form_cache, mesh, options_per_method(o.canon, o.methods, path), name, r.failures);
  for (size_t k = failures_before; k < r.failures.size(); ++k) say(o.note, "  " + describe(r.failures[k]));
  if (!computed) return std::nullopt;
  MethodForms result;
  for (size_t k = 0; k < o.methods.size(); ++k) {
    const std::string& m = o.methods[k];
    CachedForm& form = (*computed)[k];
    (form.cached ? r.forms_cached : r.forms_computed)++;
    say(o.note, detail::concat("  ", name, " ", m, ": ",
                               form.cached ? "cached" : "computed in " + fixed(form.seconds, 1) + " s",
                               form.form.repair_text.empty() ? "" : "; " + form.form.repair_text));
    result.keys[m] = form.key;
    result.forms[m] = std::move(form.form);
  }
  return result;
}

// The reference pose, its forms, and the scales every pose's rows are measured in.
struct Reference {
  const Mesh& mesh;  // the input: the scoring's geodesics
  const std::string& path;
  const Mesh& measured;         // the mesh of the forms and ICP (with resampling, the remesh)
  const Eigen::VectorXi& back;  // with resampling: per vertex of `measured`, the input's nearest
  MethodForms forms;
  std::map<std::string, double> form_diagonal;  // per method and "inputs": the form's bounding-box diagonal
  std::string content_key;                      // mesh_content_key
};

Reference reference_forms(const TopkidsInputs& in, const DiskCache& form_cache,
                          const TopkidsExperimentOptions& o, TopkidsExperimentResult& r) {
  say(o.note, "== reference " + o.reference + " (" + std::to_string(in.reference_measured.num_vertices()) +
                  " vertices)");
  std::optional<MethodForms> forms =
      forms_of(in.reference_measured, in.reference_measured_path, form_cache, o, r);
  // Every pose is measured against the reference: without its forms there is nothing to measure.
  if (!forms) fail("experiment topkids: ", describe(r.failures.back()));
  Reference ref{in.reference,
                in.reference_path,
                in.reference_measured,
                in.reference_back,
                std::move(*forms),
                {},
                mesh_content_key(in.reference)};
  for (const std::string& m : o.methods) {
    r.reference_repair[m] = ref.forms.forms[m].repair_text;
    ref.form_diagonal[m] = finite_bbox_diagonal(ref.forms.forms[m].X);
  }
  ref.form_diagonal[kInputs] = bbox_diagonal(in.reference_measured.V);
  return ref;
}

// ---- Scoring ----------------------------------------------------------------------------------------------

// The cache entry of one pose's scoring: the forms' keys, the truth files' contents and every option.
std::string scoring_entry(const TopkidsExperimentOptions& o, const Reference& reference, const Pose& p,
                          const MethodForms& forms) {
  std::ostringstream key;
  key.precision(17);
  key << "topkids-score;v3;reference=" << reference.content_key << ";pose=" << mesh_content_key(p.mesh)
      << ";ref=" << file_content_hash(p.ref_path)
      << ";sym=" << (p.sym_path.empty() ? "" : file_content_hash(p.sym_path)) << ";samples=" << o.samples
      << ";geodesics=" << to_string(o.scoring_geodesics.method) << ","
      << static_cast<int>(o.scoring_geodesics.heat_mode) << "," << o.scoring_geodesics.heat_time_factor
      << ";icp=" << to_key_string(o.icp) << ";curve=" << o.max_threshold << "," << o.curve_points;
  if (o.resample.vertices > 0)  // the maps run through the remeshes (their keys cover the forms only)
    key << ";resampled=" << mesh_content_key(reference.measured) << "," << mesh_content_key(p.measured);
  for (const std::string& m : o.methods)
    key << ";" << m << "=" << reference.forms.keys.at(m) << "," << forms.keys.at(m);
  return cache_key({key.str(), "json"});
}

// Per ground-truth vertex of the pose: its mirrored truth on the reference, −1 where there is none; empty
// when the pose has no _sym.txt. NAME_sym.txt pairs a vertex a of the pose with its mirror b on the pose
// itself (eval/correspondence_error.h), so a's mirrored truth is b's truth: ref(b).
std::vector<int> mirrored_truth(const Pose& p, const CorrespondencePairs& truth) {
  std::vector<int> symmetric;
  if (p.sym_path.empty()) return symmetric;
  const CorrespondencePairs sym =
      read_correspondence_pairs(p.sym_path, p.mesh.num_vertices(), p.mesh.num_vertices());
  const size_t n = static_cast<size_t>(p.mesh.num_vertices());
  std::vector<int> truth_of(n, -1), mirror_of(n, -1);
  for (size_t k = 0; k < truth.from.size(); ++k) truth_of[static_cast<size_t>(truth.from[k])] = truth.to[k];
  for (size_t k = 0; k < sym.from.size(); ++k)
    mirror_of[static_cast<size_t>(sym.from[k])] = truth_of[static_cast<size_t>(sym.to[k])];
  for (int a : truth.from) symmetric.push_back(mirror_of[static_cast<size_t>(a)]);
  return symmetric;
}

// One pose scored: the inputs and each method's form aligned onto the reference's by ICP, the induced maps
// scored by the SHREC'16 protocol. The cache entry's JSON: {scoring_repair, skipped_samples, sqrt_area,
// methods: {METHOD: {errors, unmapped, symmetric_chosen, direct_errors, mirrored_errors, reflected, rmse}}}.
json score_pose(const TopkidsExperimentOptions& o, const std::vector<std::string>& methods,
                const Reference& reference, const Pose& p, const MethodForms& forms) {
  const CorrespondencePairs truth =
      read_correspondence_pairs(p.ref_path, p.mesh.num_vertices(), reference.mesh.num_vertices());
  const std::vector<int> symmetric = mirrored_truth(p, truth);
  // Without resampling every vertex of the pose is mapped; with it, the carried ground-truth vertices.
  auto map = [&](const Points& source, const Points& target) {
    return o.resample.vertices > 0
               ? align_and_map_carried(source, p.measured.F, p.carried, p.mesh.num_vertices(), target,
                                       reference.back, o.icp)
               : align_and_map(source, target, o.icp);
  };
  std::vector<PointMap> maps;
  maps.push_back(map(p.measured.V, reference.measured.V));
  for (const std::string& m : o.methods)
    maps.push_back(map(forms.forms.at(m).X, reference.forms.forms.at(m).X));
  std::vector<Eigen::VectorXi> map_list;
  for (const PointMap& pm : maps) map_list.push_back(pm.map);
  CorrespondenceErrorOptions ce;
  ce.max_samples = o.samples;
  ce.max_threshold = o.max_threshold;
  ce.curve_points = o.curve_points;
  ce.geodesics = o.scoring_geodesics;
  const SymmetricCorrespondenceErrorResult s = symmetric_correspondence_errors(
      reference.mesh, map_list, truth.from, truth.to, symmetric, ce, reference.path);
  json j{{"scoring_repair", s.repair_text},
         {"skipped_samples", s.skipped_samples},
         {"sqrt_area", s.maps[0].normaliser},
         {"methods", json::object()}};
  for (size_t i = 0; i < methods.size(); ++i)
    j["methods"][methods[i]] = {{"errors", errors_to_json(s.maps[i].errors)},
                                {"unmapped", s.unmapped[i]},
                                {"symmetric_chosen", s.symmetric_chosen[i]},
                                {"direct_errors", errors_to_json(s.direct_errors[i])},
                                {"mirrored_errors", errors_to_json(s.mirrored_errors[i])},
                                {"reflected", maps[i].reflected},
                                {"rmse", maps[i].rmse}};
  return j;
}

// Per method: each measured pose's errors, in pose order, for the pooled summaries.
struct PooledErrors {
  std::map<std::string, std::vector<Eigen::VectorXd>> per_vertex;  // flip forgiven per vertex
  std::map<std::string, std::vector<Eigen::VectorXd>> whole_map;   // flip forgiven per whole map
};

// One method's row of one pose from its scoring (jm: the method's entry of score_pose's JSON); its errors
// are added to `pooled`.
TopkidsRow pose_row(const json& jm, const std::string& pose, const std::string& m, const MethodForms& forms,
                    const Reference& reference, PooledErrors& pooled) {
  TopkidsRow row;
  row.pose = pose;
  row.method = m;
  const Eigen::VectorXd e = errors_from_json(jm.at("errors"));
  row.samples = static_cast<int>(e.size());
  row.unmapped = jm.at("unmapped").get<int>();
  row.symmetric_chosen = jm.at("symmetric_chosen").get<int>();
  row.mean_error = finite_mean(e);
  row.median_error = error_median(e);
  row.under_0_1 = fraction_within(e, 0.1);
  row.under_0_25 = fraction_within(e, 0.25);
  const Eigen::VectorXd direct = errors_from_json(jm.at("direct_errors"));
  const Eigen::VectorXd mirrored = errors_from_json(jm.at("mirrored_errors"));
  row.direct_mean_error = finite_mean(direct);
  row.mirrored_mean_error = finite_mean(mirrored);
  row.whole_map_mirrored = row.mirrored_mean_error < row.direct_mean_error;
  row.mirror_ratio = row.mirrored_mean_error / row.direct_mean_error;
  row.mirrored = row.whole_map_mirrored && row.mirror_ratio <= kMirroredErrorRatio;
  const Eigen::VectorXd& whole = row.whole_map_mirrored ? mirrored : direct;
  row.whole_map_mean_error = finite_mean(whole);
  row.whole_map_under_0_1 = fraction_within(whole, 0.1);
  row.whole_map_under_0_25 = fraction_within(whole, 0.25);
  row.reflected = jm.at("reflected").get<bool>();
  row.icp_rmse = jm.at("rmse").get<double>();
  row.icp_rmse_relative = row.icp_rmse / reference.form_diagonal.at(m);
  if (m != kInputs) {
    row.repair = forms.forms.at(m).repair_text;
    const json& details = forms.forms.at(m).details;
    if (details.contains("torn_edges")) row.torn_edges = details["torn_edges"].get<long>();
  }
  pooled.whole_map[m].push_back(whole);
  pooled.per_vertex[m].push_back(e);
  return row;
}

// One query pose: its forms, its scoring (cached in misc_cache), its rows appended to r. false when the pose
// is left out (its form failed by some method).
bool measure_pose(const Pose& p, const Reference& reference, const DiskCache& form_cache,
                  const DiskCache& misc_cache, const TopkidsExperimentOptions& o, TopkidsExperimentResult& r,
                  PooledErrors& pooled) {
  const auto pose_start = WallClock::now();
  say(o.note, "== " + p.name + " (" + std::to_string(p.measured.num_vertices()) + " vertices)");
  const std::optional<MethodForms> forms = forms_of(p.measured, p.measured_path, form_cache, o, r);
  if (!forms) return false;
  const std::string entry = scoring_entry(o, reference, p, *forms);
  bool computed = false;
  const json scored = misc_cache.get_or_compute_json(entry, [&] {
    computed = true;
    return score_pose(o, r.methods, reference, p, *forms);
  });
  (computed ? r.scorings_computed : r.scorings_cached)++;
  std::ostringstream line;
  line << "  " << p.name << " done" << (computed ? "" : " (scoring cached)") << " in "
       << fixed(seconds_since(pose_start), 1) << " s; mean error";
  try {
    r.scoring_repair = scored.at("scoring_repair").get<std::string>();
    r.reference_sqrt_area = scored.at("sqrt_area").get<double>();
    for (const std::string& m : r.methods) {
      r.rows.push_back(pose_row(scored.at("methods").at(m), p.name, m, *forms, reference, pooled));
      line << " " << m << " " << fixed(r.rows.back().mean_error, 3);
    }
  } catch (const json::exception& e) {
    fail(misc_cache.entry_path(entry), ": a damaged scoring cache entry (", e.what(),
         "; delete it to recompute)");
  }
  say(o.note, line.str());
  return true;
}

// ---- Pooled summaries -------------------------------------------------------------------------------------

Eigen::VectorXd concatenate(const std::vector<Eigen::VectorXd>& parts) {
  Index total = 0;
  for (const Eigen::VectorXd& e : parts) total += e.size();
  Eigen::VectorXd all(total);
  Index at = 0;
  for (const Eigen::VectorXd& e : parts) all.segment(at, e.size()) = e, at += e.size();
  return all;
}

// The fraction of errors within each threshold.
Eigen::VectorXd cumulative_curve(const Eigen::VectorXd& errors, const Eigen::VectorXd& thresholds) {
  Eigen::VectorXd f(thresholds.size());
  for (Index t = 0; t < thresholds.size(); ++t) f[t] = fraction_within(errors, thresholds[t]);
  return f;
}

std::vector<Eigen::VectorXd> parts_of(const std::map<std::string, std::vector<Eigen::VectorXd>>& pooled,
                                      const std::string& method) {
  auto it = pooled.find(method);
  return it == pooled.end() ? std::vector<Eigen::VectorXd>{} : it->second;
}

TopkidsSummary summarise(const std::string& method, const PooledErrors& pooled,
                         const Eigen::VectorXd& thresholds) {
  const Eigen::VectorXd all = concatenate(parts_of(pooled.per_vertex, method));
  const Eigen::VectorXd whole = concatenate(parts_of(pooled.whole_map, method));
  TopkidsSummary s;
  s.method = method;
  s.samples = static_cast<int>(all.size());
  s.mean_error = finite_mean(all);
  s.median_error = error_median(all);
  s.under_0_1 = fraction_within(all, 0.1);
  s.under_0_25 = fraction_within(all, 0.25);
  s.fraction = cumulative_curve(all, thresholds);
  s.whole_map_mean_error = finite_mean(whole);
  s.whole_map_under_0_1 = fraction_within(whole, 0.1);
  s.whole_map_under_0_25 = fraction_within(whole, 0.25);
  s.whole_map_fraction = cumulative_curve(whole, thresholds);
  return s;
}

// The median of the finite values; NaN when there is none.
double finite_median(const std::vector<double>& values) {
  std::vector<double> finite;
  for (double v : values)
    if (std::isfinite(v)) finite.push_back(v);
  return finite.empty() ? NAN : error_median(Eigen::Map<const Eigen::VectorXd>(finite.data(), finite.size()));
}

// The per-pose statistics of a method's summary (TopkidsSummary::poses ...) from its rows.
void add_per_pose_statistics(TopkidsSummary& s, const std::vector<TopkidsRow>& rows) {
  std::vector<double> means, direct;
  for (const TopkidsRow& row : rows) {
    if (row.method != s.method) continue;
    ++s.poses;
    if (row.mirrored) ++s.mirrored_poses;
    means.push_back(row.mean_error);
    direct.push_back(row.direct_mean_error);
  }
  s.median_pose_mean_error = finite_median(means);
  s.median_pose_direct_error = finite_median(direct);
}

}  // namespace

std::vector<std::string> topkids_poses(const std::string& data, const std::string& reference) {
  CSHAPES_REQUIRE(fs::is_directory(data), data, ": not a folder (expected the topkids data: ", reference,
                  ".off and NAME.off with NAME_ref.txt per pose)");
  std::vector<std::string> poses;
  const std::string suffix = "_ref.txt";
  for (const auto& entry : fs::directory_iterator(data)) {
    const std::string file = entry.path().filename().string();
    if (!entry.is_regular_file() || file.size() <= suffix.size() ||
        file.compare(file.size() - suffix.size(), suffix.size(), suffix) != 0)
      continue;
    const std::string name = file.substr(0, file.size() - suffix.size());
    if (name != reference) poses.push_back(name);
  }
  std::sort(poses.begin(), poses.end());
  CSHAPES_REQUIRE(!poses.empty(), data, ": no query pose (no NAME_ref.txt besides ", reference, "'s)");
  return poses;
}

std::string topkids_mesh_path(const std::string& data, const std::string& name) {
  for (const std::string& ext : kMeshExtensions) {
    fs::path p = fs::path(data) / (name + "." + ext);
    if (fs::is_regular_file(p)) return p.string();
  }
  fail((fs::path(data) / name).string(), ": no mesh file (looked for .off .ply .obj .stl .vert)");
}

TopkidsExperimentResult run_topkids_experiment(const TopkidsExperimentOptions& o) {
  const auto start = WallClock::now();
  check_options(o);
  TopkidsExperimentResult r;
  r.poses = o.poses.empty() ? topkids_poses(o.data, o.reference) : o.poses;
  r.methods = {kInputs};
  r.methods.insert(r.methods.end(), o.methods.begin(), o.methods.end());
  TopkidsInputs inputs = read_inputs(o, r.poses);
  // Two poses (the reference among them) of the same bytes under different names: both kept, and said on
  // stderr, in report.md and in the JSON.
  std::vector<DatasetEntry> entries{{inputs.reference_path, o.reference, "kid", 0, false}};
  for (const Pose& p : inputs.poses) entries.push_back({p.mesh_path, p.name, "kid", -1, false});
  add_records(r.failures, same_content_records(entries, "poses"), o.note);

  const ExperimentFolder folder(o.out);
  if (o.resample.vertices > 0) {
    resample_inputs(o, folder, inputs, r);
    add_records(r.failures, resample_records(r.resampling), o.note);  // shapes kept at their own resolution
  }
  const DiskCache form_cache = folder.cache("forms"), misc_cache = folder.cache("misc");
  const Reference reference = reference_forms(inputs, form_cache, o, r);
  PooledErrors pooled;
  std::set<std::string> left_out;  // poses whose forms failed
  std::vector<ShapeAhead> ahead;
  for (const Pose& p : inputs.poses) ahead.push_back({&p.measured, p.measured_path});
  run_commands_ahead(form_cache, ahead, o.canon, o.methods);
  for (size_t pi = 0; pi < inputs.poses.size(); ++pi) {
    const Pose& p = inputs.poses[pi];
    if (!measure_pose(p, reference, form_cache, misc_cache, o, r, pooled)) left_out.insert(p.name);
    if (o.progress)
      o.progress("topkids", static_cast<double>(pi + 1), static_cast<double>(inputs.poses.size()));
  }
  r.poses.erase(std::remove_if(r.poses.begin(), r.poses.end(),
                               [&](const std::string& name) { return left_out.count(name) > 0; }),
                r.poses.end());
  CSHAPES_REQUIRE(!r.poses.empty(), "experiment topkids: every pose was left out (see above)");

  r.thresholds = Eigen::VectorXd::LinSpaced(o.curve_points, 0.0, o.max_threshold);
  for (const std::string& m : r.methods) {
    r.summaries.push_back(summarise(m, pooled, r.thresholds));
    add_per_pose_statistics(r.summaries.back(), r.rows);
  }

  topkids_detail::write_data_files(folder, r, o);
  r.seconds = seconds_since(start);
  return r;
}

TopkidsExperimentResult topkids_experiment(const TopkidsExperimentOptions& options) {
  OutputRun output(options.out, "experiment topkids", experiment_kept_folders(), options.force);
  start_outside_methods(options.out);
  TopkidsExperimentResult result = run_topkids_experiment(options);
  draw_topkids_figure(result, options);
  write_topkids_report(result, options, options.out);
  finish_outside_methods(options.methods, options.out, options.note);
  output.commit();
  return result;
}

}  // namespace cshapes
