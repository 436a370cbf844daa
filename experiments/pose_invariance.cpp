#include "cshapes/experiments/pose_invariance.h"
#include "cshapes/experiments/pose_invariance_detail.h"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <functional>
#include <map>
#include <optional>
#include <set>
#include <sstream>

#include <nlohmann/json.hpp>

#include "cshapes/support/csv.h"
#include "cshapes/data/dataset.h"
#include "cshapes/support/error.h"
#include "cshapes/geodesics/geodesics.h"
#include "cshapes/mesh/io.h"
#include "cshapes/mesh/mesh_repair.h"
#include "cshapes/mesh/rigid_transform.h"
#include "cshapes/support/timing.h"
#include "cshapes/support/output_folder.h"
#include "cshapes/eval/correspondence_error.h"
#include "cshapes/experiments/figures.h"
#include "cshapes/experiments/outside_methods_report.h"
#include "cshapes/pipeline/outside_methods.h"
#include "cshapes/pipeline/experiment_kit.h"
#include "cshapes/pipeline/remesh_samples.h"

namespace cshapes {

namespace fs = std::filesystem;

using pose_detail::add_part_rows;
using pose_detail::csv_number;
using pose_detail::find_parts;
using pose_detail::forms_of_run;
using pose_detail::measured_stress;
using pose_detail::PosePair;
using pose_detail::PoseShape;
using pose_detail::sample_parts;
using pose_detail::summarise_parts;
using pose_detail::summary_classes;
using pose_detail::summary_row;

namespace {

// With resampling, one shape's samples on its remesh: the input vertices some pair reads (sorted), where each
// lies on the remesh. `carried.at` is empty when the forms are computed on the input itself (no resampling,
// or a shape kept at its own resolution): its samples are then its vertices.
struct LocatedSamples {
  Index input_vertices = 0;
  RemeshSamples carried;
};

// One form of one shape as the pairs read it: a row per input vertex (with resampling, NaN but for the
// samples) and the bounding-box diagonal of the form itself, which normalises the pose RMS.
struct FormAtSamples {
  Points X;
  double diagonal = 0;
};

// Evenly spaced subset of `count` of n indices (all when count ≤ 0 or ≥ n).
std::vector<size_t> thin(size_t n, int count) {
  std::vector<size_t> keep;
  const size_t m = count <= 0 ? n : std::min(n, static_cast<size_t>(count));
  for (size_t k = 0; k < m; ++k) keep.push_back(k * n / m);
  return keep;
}

std::string stem_of(const fs::path& p) {
  return p.stem().string();
}

// A dataset (folder or manifest.csv, data/dataset.h) whose clean poses of one class share their faces, as
// `cshapes generate dataset` writes them: vertex i of one pose is vertex i of every other, so each pair of
// poses of a class is compared at all vertices. Noisy entries are left out (their faces differ by the glues).
// A class whose poses do not share faces is refused: nothing tells which vertices correspond.
void discover_shared_connectivity(const PoseInvarianceOptions& o,
                                  const std::function<bool(const std::string&)>& wanted,
                                  std::vector<PoseShape>& shapes, std::vector<PosePair>& pairs,
                                  std::vector<ShapeFailure>& left_out) {
  const Dataset data = read_dataset(o.data, o.allow_outside);
  left_out = left_out_records(data.left_out, o.canon.strict);  // folder entries that are no shape
  for (const DatasetEntry& e : data.entries)
    if (!e.noisy && wanted(e.name)) shapes.push_back({e.name, e.class_name, e.path, read_mesh(e.path), {}});
  CSHAPES_REQUIRE(
      !shapes.empty(), "experiment pose: ", o.data, " lists no clean shape",
      o.shapes.empty() ? "" : " among the shapes asked for",
      " (expected TOSCA's corres/NAME.vts, TOPKIDS's kid00.off with kidNN_ref.txt, or a dataset whose "
      "poses of a class share their faces)");
  for (size_t i = 0; i < shapes.size(); ++i)
    for (size_t j = i + 1; j < shapes.size(); ++j) {
      if (shapes[i].class_name != shapes[j].class_name) continue;
      const Mesh& a = shapes[i].mesh;
      const Mesh& b = shapes[j].mesh;
      CSHAPES_REQUIRE(
          a.num_vertices() == b.num_vertices() && a.F.rows() == b.F.rows() && a.F == b.F,
          "experiment pose: ", shapes[i].path, " and ", shapes[j].path, " (class ", shapes[i].class_name,
          ") do not share their faces (", a.num_vertices(), " and ", b.num_vertices(), " vertices, ",
          a.F.rows(), " and ", b.F.rows(),
          " faces), so vertex i of one is not known to be vertex i of the other; a dataset without "
          "shared connectivity needs TOSCA's corres/NAME.vts");
      PosePair pair;
      pair.a = static_cast<int>(i);
      pair.b = static_cast<int>(j);
      pair.va.resize(a.num_vertices());
      for (Index v = 0; v < a.num_vertices(); ++v) pair.va[v] = static_cast<int>(v);
      pair.vb = pair.va;
      pairs.push_back(std::move(pair));
    }
  CSHAPES_REQUIRE(!pairs.empty(), "experiment pose: no two clean poses of one class in ", o.data);
}

// The shapes and pairs of the folder (see the header), restricted to `only` when not empty.
// left_out: the folder's entries that are no shape (data/dataset.h), for the run's failures.
void discover(const PoseInvarianceOptions& o, std::vector<PoseShape>& shapes, std::vector<PosePair>& pairs,
              std::vector<ShapeFailure>& left_out) {
  const fs::path dir(o.data);
  const std::set<std::string> only(o.shapes.begin(), o.shapes.end());
  auto wanted = [&](const std::string& name) { return only.empty() || only.count(name); };
  if (fs::is_regular_file(dir)) {  // a manifest.csv
    discover_shared_connectivity(o, wanted, shapes, pairs, left_out);
    return;
  }
  CSHAPES_REQUIRE(fs::is_directory(dir), "experiment pose: ", o.data, " is neither a folder nor a manifest");
  if (fs::exists(dir / "kid00.off")) {
    // TOPKIDS: kid00 is the reference; every kidNN with a _ref.txt is a pose.
    std::vector<std::string> poses;
    for (const auto& e : fs::directory_iterator(dir)) {
      const std::string f = e.path().filename().string();
      const std::string suffix = "_ref.txt";
      if (f.size() > suffix.size() && f.compare(f.size() - suffix.size(), suffix.size(), suffix) == 0) {
        const std::string name = f.substr(0, f.size() - suffix.size());
        if (wanted(name) && fs::exists(dir / (name + ".off"))) poses.push_back(name);
      }
    }
    std::sort(poses.begin(), poses.end());
    CSHAPES_REQUIRE(!poses.empty(), "experiment pose: ", o.data, " has kid00.off but no kidNN_ref.txt pose");
    shapes.push_back({"kid00", "kid", (dir / "kid00.off").string(), {}, {}});
    for (const std::string& p : poses) shapes.push_back({p, "kid", (dir / (p + ".off")).string(), {}, {}});
    for (PoseShape& s : shapes) s.mesh = read_mesh(s.path);
    for (size_t k = 1; k < shapes.size(); ++k) {
      PosePair pair;
      pair.a = static_cast<int>(k);
      pair.b = 0;
      CorrespondencePairs truth =
          read_correspondence_pairs((dir / (shapes[k].name + "_ref.txt")).string(),
                                    shapes[k].mesh.num_vertices(), shapes[0].mesh.num_vertices());
      pair.va = std::move(truth.from);
      pair.vb = std::move(truth.to);
      pairs.push_back(std::move(pair));
    }
    return;
  }
  if (!fs::is_directory(dir / "corres")) {
    discover_shared_connectivity(o, wanted, shapes, pairs, left_out);
    return;
  }
  // TOSCA: NAME.off with corres/NAME.vts; pairs within a class.
  for (const auto& e : fs::directory_iterator(dir)) {
    if (!e.is_regular_file() || e.path().extension() != ".off") continue;
    const std::string name = stem_of(e.path());
    if (!wanted(name)) continue;
    const fs::path vts = dir / "corres" / (name + ".vts");
    if (!fs::exists(vts)) continue;
    shapes.push_back({name, class_from_name(name), e.path().string(), {}, {}});
  }
  std::sort(shapes.begin(), shapes.end(),
            [](const PoseShape& x, const PoseShape& y) { return x.name < y.name; });
  CSHAPES_REQUIRE(!shapes.empty(), "experiment pose: no NAME.off with corres/NAME.vts in ", o.data,
                  only.empty() ? "" : " among the shapes asked for");
  for (PoseShape& s : shapes) {
    s.mesh = read_mesh(s.path);
    s.vts = read_vts((dir / "corres" / (s.name + ".vts")).string(), s.mesh.num_vertices());
  }
  for (size_t i = 0; i < shapes.size(); ++i)
    for (size_t j = i + 1; j < shapes.size(); ++j) {
      if (shapes[i].class_name != shapes[j].class_name) continue;
      CSHAPES_REQUIRE(shapes[i].vts.size() == shapes[j].vts.size(), "experiment pose: ", shapes[i].name,
                      ".vts and ", shapes[j].name, ".vts list different numbers of samples");
      pairs.push_back({static_cast<int>(i), static_cast<int>(j), shapes[i].vts, shapes[j].vts});
    }
  CSHAPES_REQUIRE(!pairs.empty(), "experiment pose: no two poses of one class in ", o.data);
}

// One form's whole-shape rigid fit of a pair: the pose RMS (see the header) and each kept sample's residual
// ‖R·a_s + t − b_s‖ after that fit, both over the mean diagonal; NaN where a sample is not finite in both.
struct PairFit {
  double rms = 0;
  Eigen::VectorXd residuals;  // per kept sample
};

PairFit pair_fit(const FormAtSamples& A, const FormAtSamples& B, const PosePair& pair,
                 const std::vector<size_t>& keep) {
  Points SA(static_cast<Index>(keep.size()), 3), SB(static_cast<Index>(keep.size()), 3);
  for (size_t k = 0; k < keep.size(); ++k) {
    SA.row(static_cast<Index>(k)) = A.X.row(pair.va[keep[k]]);
    SB.row(static_cast<Index>(k)) = B.X.row(pair.vb[keep[k]]);
  }
  RigidFitOptions fit;
  fit.determinant = 0;
  fit.skip_nonfinite_rows = true;
  const RigidFitResult r = fit_rigid_transform(SA, SB, fit);
  const double scale = 0.5 * (A.diagonal + B.diagonal);
  PairFit out;
  out.rms = r.rms / scale;
  out.residuals = (r.transform.apply(SA) - SB).rowwise().norm() / scale;
  return out;
}

// ---- Resampling -------------------------------------------------------------------------------------------

// The input vertices each shape's pairs read (the samples of measure_pairs), sorted.
std::vector<std::vector<int>> sampled_vertices(size_t shape_count, const std::vector<PosePair>& pairs,
                                               int samples) {
  std::vector<std::set<int>> sets(shape_count);
  for (const PosePair& p : pairs)
    for (size_t k : thin(p.va.size(), samples)) {
      sets[p.a].insert(p.va[k]);
      sets[p.b].insert(p.vb[k]);
    }
  std::vector<std::vector<int>> out(shape_count);
  for (size_t i = 0; i < shape_count; ++i) out[i].assign(sets[i].begin(), sets[i].end());
  return out;
}

// Remeshes the shapes (only those of the run), then replaces each shape's mesh and path by its remesh and
// locates its samples there: result.resampling and result.located are set, the returned list says where each
// shape's samples lie.
std::vector<LocatedSamples> resample_shapes(const PoseInvarianceOptions& o, const ExperimentFolder& folder,
                                            const std::vector<PosePair>& pairs,
                                            std::vector<PoseShape>& shapes, PoseInvarianceResult& result) {
  Dataset inputs;
  inputs.source = o.data;
  std::map<std::string, int> poses_of_class;
  for (const PoseShape& s : shapes)
    inputs.entries.push_back({s.path, s.name, s.class_name, poses_of_class[s.class_name]++, false});
  result.resampled = true;
  result.resampling = resample_dataset(inputs, o.resample, folder.path("resampled"), folder.cache("remeshed"),
                                       nullptr, o.note);
  std::map<std::string, const ResampledShape*> remesh_of;
  for (const ResampledShape& r : result.resampling.shapes) remesh_of[r.name] = &r;

  const std::vector<std::vector<int>> samples = sampled_vertices(shapes.size(), pairs, o.samples);
  std::vector<LocatedSamples> located(shapes.size());
  for (size_t i = 0; i < shapes.size(); ++i) {
    PoseShape& s = shapes[i];
    LocatedSamples& l = located[i];
    l.input_vertices = s.mesh.num_vertices();
    PoseLocatedRow row;
    row.shape = s.name;
    row.samples = static_cast<int>(samples[i].size());
    const auto found = remesh_of.find(s.name);
    CSHAPES_REQUIRE(found != remesh_of.end(), "experiment pose: ", s.path, " was not resampled");
    const ResampledShape& r = *found->second;
    row.remeshed = r.remeshed;
    if (r.remeshed) {
      const Mesh remeshed = read_mesh(r.file);
      l.carried = carry_to_remesh(s.mesh, remeshed, samples[i]);
      row.mean_distance = l.carried.mean_distance;
      row.max_distance = l.carried.max_distance;
      row.relocated = l.carried.relocated;
      row.off_part = l.carried.off_part;
      s.mesh = remeshed;
      s.path = r.file;
      say(o.note, detail::concat("  ", s.name, ": ", row.samples, " samples located on the remesh, ",
                                 carried_summary(l.carried)));
    }
    result.located.push_back(row);
  }
  return located;
}

// A form (n×3, a row per vertex of the mesh it was computed on) at the shape's samples (see FormAtSamples).
FormAtSamples at_samples(const Points& X, const Faces& F, const LocatedSamples& located) {
  FormAtSamples out;
  out.diagonal = finite_bbox_diagonal(X);
  const RemeshSamples& carried = located.carried;
  if (carried.at.face.size() == 0) {
    out.X = X;
    return out;
  }
  const Eigen::MatrixXd values = interpolate_on_surface(F, carried.at, X);
  out.X.setConstant(located.input_vertices, 3, NAN);
  for (size_t k = 0; k < carried.vertices.size(); ++k)
    out.X.row(carried.vertices[k]) = values.row(static_cast<Index>(k));
  return out;
}

// Stretch statistics over the mesh edges with finite ends; edges between two torn vertices are left out
// (they include every torn edge; CanonicalForm records torn vertices, not edges).
void stretch_stats(const Mesh& mesh, const Points& X, const Eigen::VectorXd& torn, PoseShapeRow& row) {
  const Edges E = mesh_edges(mesh.F);
  std::vector<double> s;
  s.reserve(E.rows());
  for (Index e = 0; e < E.rows(); ++e) {
    const int i = E(e, 0), j = E(e, 1);
    if (torn.size() && torn[i] > 0 && torn[j] > 0) continue;
    if (!X.row(i).allFinite() || !X.row(j).allFinite()) continue;
    const double l0 = (mesh.V.row(i) - mesh.V.row(j)).norm();
    if (!(l0 > 0)) continue;
    s.push_back((X.row(i) - X.row(j)).norm() / l0);
  }
  if (s.empty()) return;
  double sum = 0;
  for (double v : s) sum += std::abs(v - 1);
  row.mean_abs_stretch = sum / s.size();
  row.max_stretch = *std::max_element(s.begin(), s.end());
  const size_t k = std::min(s.size() - 1, static_cast<size_t>(std::ceil(0.99 * s.size())) - 1);
  std::nth_element(s.begin(), s.begin() + k, s.end());
  row.p99_stretch = s[k];
}

// Fast-marching distances from `count` evenly spaced sources of the manifold repair, at the input's
// vertices (NaN where the repair dropped a vertex): sources × n.
struct StressReference {
  std::vector<int> sources;  // input vertex indices
  Eigen::MatrixXd g;         // sources × n
};

StressReference stress_reference(const PoseShape& s, int count) {
  StressReference ref;
  if (count <= 0) return ref;
  RepairOptions ro;
  ro.name = s.path;
  ro.purpose = "the stress's fast marching";
  const RepairedMesh r = repair_for(s.mesh, MeshRequirements::manifold_surface(), ro);
  const Index m = r.mesh.num_vertices();
  const Index n = s.mesh.num_vertices();
  GeodesicOptions go;
  go.method = GeodesicMethod::FastMarching;
  const std::vector<size_t> picks = thin(static_cast<size_t>(m), count);
  ref.g.setConstant(static_cast<Index>(picks.size()), n, NAN);
  ref.sources.resize(picks.size());
#pragma omp parallel for schedule(dynamic)
  for (long k = 0; k < static_cast<long>(picks.size()); ++k) {
    const Eigen::VectorXd d = geodesic_distances(r.mesh, {static_cast<int>(picks[k])}, go);
    for (Index v = 0; v < m; ++v) ref.g(k, r.vertex_map[v]) = d[v];
    ref.sources[k] = r.vertex_map[picks[k]];
  }
  return ref;
}

double geodesic_stress(const Points& X, const StressReference& ref) {
  if (ref.sources.empty()) return -1;
  double num = 0, den = 0;
  for (size_t k = 0; k < ref.sources.size(); ++k) {
    const int src = ref.sources[k];
    if (!X.row(src).allFinite()) continue;
    for (Index i = 0; i < X.rows(); ++i) {
      const double g = ref.g(static_cast<Index>(k), i);
      if (!std::isfinite(g) || !X.row(i).allFinite()) continue;
      const double d = (X.row(i) - X.row(src)).norm();
      num += (d - g) * (d - g);
      den += g * g;
    }
  }
  return den > 0 ? std::sqrt(num / den) : -1;
}

// ---- Measurement ------------------------------------------------------------------------------------------

void check_methods(const PoseInvarianceOptions& o) {
  require_canonical_form_methods(o.methods, "experiment pose");
}

// Every form of every shape at its samples: X[form][shape index] (empty for a shape left out).
using FormPoints = std::map<std::string, std::vector<FormAtSamples>>;

// One shape's row for one method's form: stretch, stress against `reference`, cost; said in a note.
PoseShapeRow form_row(const PoseShape& s, const std::string& method, const CachedForm& computed,
                      const StressReference& reference, const NoteFn& note) {
  const CanonicalForm& form = computed.form;
  PoseShapeRow row;
  row.shape = s.name;
  row.form = method;
  stretch_stats(s.mesh, form.X, form.torn, row);
  row.stress = geodesic_stress(form.X, reference);
  row.iterations = form.iterations;
  row.seconds = form.precompute_seconds + form.solve_seconds;
  if (form.torn.size()) row.torn_edges = static_cast<int>(form.torn.sum());  // torn vertices
  say(note,
      detail::concat("  ", s.name, " ", method, computed.cached ? " (cached)" : "", ": ", form.iterations,
                     " iterations, ", fixed(row.seconds, 2), " s, mean |stretch-1| ",
                     fixed(row.mean_abs_stretch, 3), ", stress ", fixed(measured_stress(row.stress), 3)));
  return row;
}

// Shape i: its forms by every method (cached), its rows of result.shapes (the input's first), its forms at
// its samples in X. false when a form failed: the shape is left out (its record in result.failures).
bool measure_shape(const PoseShape& s, size_t i, const LocatedSamples& located, const DiskCache& cache,
                   const PoseInvarianceOptions& o, FormPoints& X, PoseInvarianceResult& result) {
  const size_t failures_before = result.failures.size();
  std::optional<std::vector<CachedForm>> computed = shape_canonical_forms(
      cache, s.mesh, options_per_method(o.canon, o.methods, s.path), s.name, result.failures);
  for (size_t k = failures_before; k < result.failures.size(); ++k)
    say(o.note, "  " + describe(result.failures[k]));
  if (!computed) return false;
  X["input"][i] = at_samples(s.mesh.V, s.mesh.F, located);
  const StressReference reference = stress_reference(s, o.stress_sources);
  PoseShapeRow input_row;
  input_row.shape = s.name;
  input_row.form = "input";
  input_row.stress = geodesic_stress(s.mesh.V, reference);
  result.shapes.push_back(input_row);
  for (size_t k = 0; k < o.methods.size(); ++k) {
    result.shapes.push_back(form_row(s, o.methods[k], (*computed)[k], reference, o.note));
    X[o.methods[k]][i] = at_samples((*computed)[k].form.X, s.mesh.F, located);
  }
  return true;
}

// Every pair of two measured shapes: one row per form, said in a note.
// Every pair of two measured shapes: one row per form (and per part, with parts), said in a note.
void measure_pairs(const std::vector<PoseShape>& shapes, const std::vector<PosePair>& pairs,
                   const std::vector<char>& failed, const FormPoints& X,
                   const std::vector<std::vector<int>>& part_of, const PoseInvarianceOptions& o,
                   PoseInvarianceResult& result) {
  const std::vector<std::string> forms = forms_of_run(o);
  for (const PosePair& p : pairs) {
    if (failed[p.a] || failed[p.b]) continue;
    const std::vector<size_t> keep = thin(p.va.size(), o.samples);
    const std::vector<int> parts = sample_parts(p, keep, part_of);
    const double input_rms = pair_fit(X.at("input")[p.a], X.at("input")[p.b], p, keep).rms;
    std::string line = "  " + shapes[p.a].name + "-" + shapes[p.b].name + ":";
    for (const std::string& f : forms) {
      const PairFit fit = pair_fit(X.at(f)[p.a], X.at(f)[p.b], p, keep);
      PosePairRow row;
      row.a = shapes[p.a].name;
      row.b = shapes[p.b].name;
      row.class_name = shapes[p.a].class_name;
      row.form = f;
      row.rms = fit.rms;
      row.input_rms = input_rms;
      row.samples = static_cast<int>(keep.size());
      result.pairs.push_back(row);
      if (o.parts) add_part_rows(row, fit.residuals, parts, result);
      line += " " + f + " " + percent(row.rms);
    }
    say(o.note, line);
  }
}

// The figure's pair: the one with the median pose RMS of Coulomb (else of the first method, else of the
// input; the lower middle one for an even count), its samples at pose b's input positions and each form's
// residuals there. inputs: per shape, its input vertex positions (before any resampling).
PoseFigurePair figure_pair(const std::vector<PoseShape>& shapes, const std::vector<PosePair>& pairs,
                           const FormPoints& X, const std::vector<std::vector<int>>& part_of,
                           const std::vector<Points>& inputs, const PoseInvarianceOptions& o,
                           const PoseInvarianceResult& result) {
  PoseFigurePair fig;
  const std::vector<std::string> forms = forms_of_run(o);
  const std::string by = std::find(o.methods.begin(), o.methods.end(), "coulomb") != o.methods.end()
                             ? "coulomb"
                         : forms.size() > 1 ? forms[1]
                                            : "input";
  std::vector<const PosePairRow*> rows;
  for (const PosePairRow& r : result.pairs)
    if (r.form == by) rows.push_back(&r);
  if (rows.empty()) return fig;
  std::stable_sort(rows.begin(), rows.end(),
                   [](const PosePairRow* x, const PosePairRow* y) { return x->rms < y->rms; });
  const size_t middle = (rows.size() - 1) / 2;
  const PosePairRow& chosen = *rows[middle];
  const std::string by_title = by == "input" ? "input" : canonical_form_method_title(by);
  fig.a = chosen.a;
  fig.b = chosen.b;
  fig.class_name = chosen.class_name;
  fig.chosen_by = detail::concat("the pair with the median ", by_title, " pose RMS (", middle + 1, " of ",
                                 rows.size(), " pairs by increasing RMS)");
  const PosePair* pair = nullptr;
  for (const PosePair& p : pairs)
    if (shapes[p.a].name == chosen.a && shapes[p.b].name == chosen.b) pair = &p;
  CSHAPES_REQUIRE(pair != nullptr, "experiment pose: the figure's pair ", chosen.a, "-", chosen.b,
                  " is gone");
  const std::vector<size_t> keep = thin(pair->va.size(), o.samples);
  fig.parts = sample_parts(*pair, keep, part_of);
  fig.positions.resize(static_cast<Index>(keep.size()), 3);
  for (size_t k = 0; k < keep.size(); ++k) {
    fig.vertices.push_back(pair->vb[keep[k]]);
    fig.positions.row(static_cast<Index>(k)) = inputs[pair->b].row(pair->vb[keep[k]]);
  }
  fig.forms = forms;
  fig.residuals.resize(static_cast<Index>(keep.size()), static_cast<Index>(forms.size()));
  for (size_t f = 0; f < forms.size(); ++f) {
    const PairFit fit = pair_fit(X.at(forms[f])[pair->a], X.at(forms[f])[pair->b], *pair, keep);
    fig.rms.push_back(fit.rms);
    fig.residuals.col(static_cast<Index>(f)) = fit.residuals;
  }
  return fig;
}

}  // namespace

PoseInvarianceResult run_pose_invariance(const PoseInvarianceOptions& o) {
  check_methods(o);
  std::vector<PoseShape> shapes;
  std::vector<PosePair> pairs;
  std::vector<ShapeFailure> left_out;
  discover(o, shapes, pairs, left_out);
  say(o.note,
      detail::concat("experiment pose: ", shapes.size(), " shapes, ", pairs.size(), " pairs of poses"));

  const ExperimentFolder folder(o.out);
  const DiskCache cache = folder.cache("forms");
  PoseInvarianceResult result;
  // Two poses of the same bytes under different names: both kept (their pair shows no pose variation), and
  // said on stderr and in pose.md.
  std::vector<DatasetEntry> entries;
  for (const PoseShape& s : shapes) entries.push_back({s.path, s.name, s.class_name, -1, false});
  add_records(result.failures, same_content_records(entries, "poses"), o.note);
  add_records(result.failures, left_out, o.note);
  // On the inputs, before any resampling: the parts, and the positions the figure shows.
  const std::vector<std::vector<int>> part_of = find_parts(o, shapes, pairs, result);
  std::vector<Points> inputs;
  for (const PoseShape& s : shapes) inputs.push_back(s.mesh.V);
  std::vector<LocatedSamples> located(shapes.size());
  if (o.resample.vertices > 0) {
    located = resample_shapes(o, folder, pairs, shapes, result);
    // A shape kept at its own resolution, with the reason.
    add_records(result.failures, resample_records(result.resampling), o.note);
  }
  FormPoints X;
  for (const std::string& f : forms_of_run(o)) X[f].resize(shapes.size());
  std::vector<char> failed(shapes.size(), 0);
  std::vector<ShapeAhead> ahead;
  for (const PoseShape& s : shapes) ahead.push_back({&s.mesh, s.path});
  run_commands_ahead(cache, ahead, o.canon, o.methods);
  for (size_t i = 0; i < shapes.size(); ++i)
    failed[i] = !measure_shape(shapes[i], i, located[i], cache, o, X, result);
  measure_pairs(shapes, pairs, failed, X, part_of, o, result);
  summarise_parts(forms_of_run(o), result);
  result.figure_pair = figure_pair(shapes, pairs, X, part_of, inputs, o, result);

  std::map<std::string, std::string> class_of;
  for (const PoseShape& s : shapes) class_of[s.name] = s.class_name;
  for (const std::string& f : forms_of_run(o))
    for (const std::string& c : summary_classes(shapes, failed))
      result.summary.push_back(summary_row(f, c, result, class_of));

  pose_detail::write_data_files(folder, o, result);
  return result;
}

void draw_pose_figure(PoseInvarianceResult& result, const PoseInvarianceOptions& options) {
  result.figure = "";
  if (result.figure_pair.a.empty()) {
    result.figure_problem = "no pair was measured";
  } else if (!options.figure) {
    result.figure_problem = "not requested (--no-draw)";
  } else {
    const FigureRun drawn =
        draw_figure("pose_figure.py", {options.out}, ExperimentFolder(options.out).path("pose_residuals"),
                    options.figure_format, options.methods);
    if (drawn.drawn) result.figure = figure_file_name("pose_residuals", options.figure_format);
    result.figure_problem = drawn.problem;
  }
}

PoseInvarianceResult pose_experiment(const PoseInvarianceOptions& options) {
  OutputRun output(options.out, "experiment pose", experiment_kept_folders(), options.force);
  start_outside_methods(options.out);
  PoseInvarianceResult result = run_pose_invariance(options);
  draw_pose_figure(result, options);
  write_pose_invariance_report(result, options, options.out);
  finish_outside_methods(options.methods, options.out, options.note, "pose.md");
  output.commit();
  return result;
}

}  // namespace cshapes
