#include "experiments/pose_invariance.h"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <functional>
#include <map>
#include <optional>
#include <set>
#include <sstream>

#include <nlohmann/json.hpp>

#include "core/csv.h"
#include "core/dataset.h"
#include "core/error.h"
#include "core/geodesics.h"
#include "core/io.h"
#include "core/mesh_repair.h"
#include "core/rigid_transform.h"
#include "core/timing.h"
#include "eval/correspondence_error.h"
#include "experiments/figures.h"
#include "pipeline/experiment_kit.h"
#include "pipeline/remesh_samples.h"

namespace cshapes {

namespace fs = std::filesystem;

namespace {

struct PoseShape {
  std::string name, class_name, path;
  Mesh mesh;
  std::vector<int> vts;  // TOSCA: the sample list of corres/NAME.vts
};

struct PosePair {
  int a = 0, b = 0;         // shape indices
  std::vector<int> va, vb;  // corresponding vertices (0-based), equal lengths
};

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

// A dataset (folder or manifest.csv, core/dataset.h) whose clean poses of one class share their faces, as
// `cshapes generate dataset` writes them: vertex i of one pose is vertex i of every other, so each pair of
// poses of a class is compared at all vertices. Noisy entries are left out (their faces differ by the glues).
// A class whose poses do not share faces is refused: nothing tells which vertices correspond.
void discover_shared_connectivity(const PoseInvarianceOptions& o,
                                  const std::function<bool(const std::string&)>& wanted,
                                  std::vector<PoseShape>& shapes, std::vector<PosePair>& pairs,
                                  std::vector<ShapeFailure>& left_out) {
  const Dataset data = read_dataset(o.data);
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
// left_out: the folder's entries that are no shape (core/dataset.h), for the run's failures.
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

// A number in a CSV cell: 6 significant digits; empty when not finite.
std::string csv_number(double v, int precision = 6) {
  if (!std::isfinite(v)) return "";
  std::ostringstream s;
  s.precision(precision);
  s << v;
  return s.str();
}

// A geodesic stress for a report: NaN (shown "—") when not measured (−1).
double measured_stress(double stress) {
  return stress >= 0 ? stress : NAN;
}

// ---- Parts ------------------------------------------------------------------------------------------------

// Per shape, per input vertex: its part (−1: unknown). Each class's parts are found on its first pose and
// carried to the other poses through the pairs with the first pose (every correspondence of the pair, not
// only the kept samples). result.classes gets one entry per class.
std::vector<std::vector<int>> find_parts(const PoseInvarianceOptions& o, const std::vector<PoseShape>& shapes,
                                         const std::vector<PosePair>& pairs, PoseInvarianceResult& result) {
  std::vector<std::vector<int>> part_of(shapes.size());
  for (size_t i = 0; i < shapes.size(); ++i)
    part_of[i].assign(static_cast<size_t>(shapes[i].mesh.num_vertices()), -1);
  if (!o.parts) return part_of;
  std::map<std::string, size_t> first_of_class;
  for (size_t i = 0; i < shapes.size(); ++i) first_of_class.emplace(shapes[i].class_name, i);
  std::vector<size_t> firsts;
  for (size_t i = 0; i < shapes.size(); ++i)
    if (first_of_class.at(shapes[i].class_name) == i) firsts.push_back(i);
  for (size_t f : firsts) {
    const PoseShape& s = shapes[f];
    PoseClassParts c;
    c.class_name = s.class_name;
    c.shape = s.name;
    try {
      const GeodesicPartsResult parts = geodesic_parts(s.mesh, o.part_finder);
      c.centre = parts.centre;
      c.extremities = parts.extremities;
      c.reach = parts.extremity_reach;
      c.persistence = parts.extremity_persistence;
      c.repair_text = parts.repair_text;
      part_of[f].assign(parts.part.data(), parts.part.data() + parts.part.size());
    } catch (const Error& e) {
      c.problem = e.what();
    }
    say(o.note, c.problem.empty() ? detail::concat("  parts of ", c.class_name, " on ", s.name, ": ",
                                                   c.extremities.size(), " extremities and the core")
                                  : detail::concat("  parts of ", c.class_name, ": none (", c.problem, ")"));
    result.classes.push_back(c);
  }
  for (const PosePair& p : pairs) {
    const size_t f = first_of_class.at(shapes[p.a].class_name);
    if (static_cast<size_t>(p.a) == f)
      for (size_t k = 0; k < p.va.size(); ++k) part_of[p.b][p.vb[k]] = part_of[f][p.va[k]];
    else if (static_cast<size_t>(p.b) == f)
      for (size_t k = 0; k < p.vb.size(); ++k) part_of[p.a][p.va[k]] = part_of[f][p.vb[k]];
  }
  return part_of;
}

// The part of each kept sample of a pair: its vertex's part on a, else on b, else −1.
std::vector<int> sample_parts(const PosePair& p, const std::vector<size_t>& keep,
                              const std::vector<std::vector<int>>& part_of) {
  std::vector<int> parts(keep.size(), -1);
  for (size_t k = 0; k < keep.size(); ++k) {
    const int on_a = part_of[p.a][p.va[keep[k]]];
    parts[k] = on_a >= 0 ? on_a : part_of[p.b][p.vb[keep[k]]];
  }
  return parts;
}

// One pair and form: a row per part that has samples (finite residuals), the unassigned ones as part −1.
void add_part_rows(const PosePairRow& pair_row, const Eigen::VectorXd& residuals,
                   const std::vector<int>& parts, PoseInvarianceResult& result) {
  std::map<int, std::pair<double, int>> squares;  // part → (Σ residual², samples)
  for (Index k = 0; k < residuals.size(); ++k) {
    if (!std::isfinite(residuals[k])) continue;
    auto& [sum, count] = squares[parts[static_cast<size_t>(k)]];
    sum += residuals[k] * residuals[k];
    ++count;
  }
  for (const auto& [part, sum_count] : squares) {
    PosePartRow row;
    row.a = pair_row.a;
    row.b = pair_row.b;
    row.class_name = pair_row.class_name;
    row.form = pair_row.form;
    row.part = part;
    row.samples = sum_count.second;
    row.rms = std::sqrt(sum_count.first / sum_count.second);
    result.parts.push_back(row);
  }
}

// Medians over the pairs per class, part and form, in the order of result.classes, parts −1 (when any), 0,
// 1, ..., forms in run order.
void summarise_parts(const std::vector<std::string>& forms, PoseInvarianceResult& result) {
  for (const PoseClassParts& c : result.classes) {
    std::set<int> parts;
    for (const PosePartRow& r : result.parts)
      if (r.class_name == c.class_name) parts.insert(r.part);
    for (int part : parts)
      for (const std::string& f : forms) {
        PosePartSummaryRow row;
        row.class_name = c.class_name;
        row.form = f;
        row.part = part;
        std::vector<double> rms, samples;
        for (const PosePartRow& r : result.parts)
          if (r.class_name == c.class_name && r.form == f && r.part == part) {
            rms.push_back(r.rms);
            samples.push_back(r.samples);
          }
        row.pairs = static_cast<int>(rms.size());
        row.median_rms = rms.empty() ? NAN : median(rms);
        row.median_samples = samples.empty() ? 0 : median(samples);
        result.part_summary.push_back(row);
      }
  }
}

// ---- Measurement ------------------------------------------------------------------------------------------

// The forms the run measures: "input" (the meshes themselves), then the options' methods.
std::vector<std::string> forms_of_run(const PoseInvarianceOptions& o) {
  std::vector<std::string> forms = {"input"};
  forms.insert(forms.end(), o.methods.begin(), o.methods.end());
  return forms;
}

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

// ---- Summary ----------------------------------------------------------------------------------------------

// "all", then each class of a measured shape in shape order; "all" alone when there is one class.
std::vector<std::string> summary_classes(const std::vector<PoseShape>& shapes,
                                         const std::vector<char>& failed) {
  std::vector<std::string> classes = {"all"};
  for (size_t i = 0; i < shapes.size(); ++i)
    if (!failed[i] && std::find(classes.begin(), classes.end(), shapes[i].class_name) == classes.end())
      classes.push_back(shapes[i].class_name);
  if (classes.size() == 2) classes.pop_back();  // one class: "all" says it
  return classes;
}

// One form over the pairs and shapes of one class ("all": every class). class_of: shape name → class.
PoseSummaryRow summary_row(const std::string& form, const std::string& class_name,
                           const PoseInvarianceResult& result,
                           const std::map<std::string, std::string>& class_of) {
  PoseSummaryRow row;
  row.form = form;
  row.class_name = class_name;
  std::vector<double> rms, input;
  for (const PosePairRow& p : result.pairs)
    if (p.form == form && (class_name == "all" || p.class_name == class_name)) {
      rms.push_back(p.rms);
      input.push_back(p.input_rms);
    }
  row.pairs = static_cast<int>(rms.size());
  row.median_rms = median(rms);
  row.median_input_rms = median(input);
  double sum = 0;
  for (double v : rms) sum += v;
  row.mean_rms = rms.empty() ? NAN : sum / rms.size();
  row.removed = 1 - row.median_rms / row.median_input_rms;
  std::vector<double> stretch, stress;
  for (const PoseShapeRow& s : result.shapes)
    if (s.form == form && (class_name == "all" || class_of.at(s.shape) == class_name)) {
      stretch.push_back(s.mean_abs_stretch);
      row.max_stretch = std::max(row.max_stretch, s.max_stretch);
      if (s.stress >= 0) stress.push_back(s.stress);
    }
  row.mean_abs_stretch = median(stretch);
  row.stress = stress.empty() ? -1 : median(stress);
  return row;
}

// ---- Data files -------------------------------------------------------------------------------------------

// Text fields quoted where they must be: a label "a,b" stays one column.
void write_pairs_csv(const ExperimentFolder& folder, const std::string& label,
                     const PoseInvarianceResult& result) {
  std::ostringstream csv;
  csv << "config,a,b,class,form,rms,input_rms,samples\n";
  for (const PosePairRow& r : result.pairs)
    csv << csv_field(label) << "," << csv_field(r.a) << "," << csv_field(r.b) << ","
        << csv_field(r.class_name) << "," << csv_field(r.form) << "," << csv_number(r.rms) << ","
        << csv_number(r.input_rms) << "," << r.samples << "\n";
  folder.write_text("pose_pairs.csv", csv.str());
}

void write_shapes_csv(const ExperimentFolder& folder, const std::string& label,
                      const PoseInvarianceResult& result) {
  std::ostringstream csv;
  csv << "config,shape,form,mean_abs_stretch,p99_stretch,max_stretch,geodesic_stress,iterations,seconds,"
         "torn_vertices\n";
  for (const PoseShapeRow& r : result.shapes)
    csv << csv_field(label) << "," << csv_field(r.shape) << "," << csv_field(r.form) << ","
        << csv_number(r.mean_abs_stretch) << "," << csv_number(r.p99_stretch) << ","
        << csv_number(r.max_stretch) << "," << (r.stress >= 0 ? csv_number(r.stress) : "") << ","
        << r.iterations << "," << csv_number(r.seconds, 4) << "," << r.torn_edges << "\n";
  folder.write_text("pose_shapes.csv", csv.str());
}

void write_summary_csv(const ExperimentFolder& folder, const std::string& label,
                       const PoseInvarianceResult& result) {
  std::ostringstream csv;
  csv << "config,form,class,pairs,median_rms,mean_rms,median_input_rms,removed,median_mean_abs_stretch,"
         "max_stretch,median_geodesic_stress\n";
  for (const PoseSummaryRow& r : result.summary)
    csv << csv_field(label) << "," << csv_field(r.form) << "," << csv_field(r.class_name) << "," << r.pairs
        << "," << csv_number(r.median_rms) << "," << csv_number(r.mean_rms) << ","
        << csv_number(r.median_input_rms) << "," << csv_number(r.removed) << ","
        << csv_number(r.mean_abs_stretch) << "," << csv_number(r.max_stretch) << ","
        << (r.stress >= 0 ? csv_number(r.stress) : "") << "\n";
  folder.write_text("pose_summary.csv", csv.str());
}

void write_parts_csv(const ExperimentFolder& folder, const std::string& label,
                     const PoseInvarianceResult& result) {
  std::map<std::string, const PoseClassParts*> class_parts;
  for (const PoseClassParts& c : result.classes) class_parts[c.class_name] = &c;
  std::ostringstream csv;
  csv << "config,a,b,class,form,part,parts_shape,extremity_vertex,samples,rms\n";
  for (const PosePartRow& r : result.parts) {
    const PoseClassParts& c = *class_parts.at(r.class_name);
    csv << csv_field(label) << "," << csv_field(r.a) << "," << csv_field(r.b) << ","
        << csv_field(r.class_name) << "," << csv_field(r.form) << "," << r.part << "," << csv_field(c.shape)
        << "," << (r.part >= 1 ? std::to_string(c.extremities[static_cast<size_t>(r.part - 1)]) : "") << ","
        << r.samples << "," << csv_number(r.rms) << "\n";
  }
  folder.write_text("pose_parts.csv", csv.str());
}

// The figure's data: pose_residuals.csv (a row per sample: its vertex of b, position, part, and per form the
// residual) and pose_residuals.json (the pair, why, the forms and their pose RMS).
void write_figure_data(const ExperimentFolder& folder, const PoseFigurePair& fig) {
  std::ostringstream csv;
  csv << "sample,vertex,x,y,z,part";
  for (const std::string& f : fig.forms) csv << "," << csv_field(f);
  csv << "\n";
  for (Index k = 0; k < fig.positions.rows(); ++k) {
    csv << k << "," << fig.vertices[static_cast<size_t>(k)];
    for (int c = 0; c < 3; ++c) csv << "," << csv_number(fig.positions(k, c), 9);
    csv << "," << fig.parts[static_cast<size_t>(k)];
    for (Index f = 0; f < fig.residuals.cols(); ++f) csv << "," << csv_number(fig.residuals(k, f));
    csv << "\n";
  }
  folder.write_text("pose_residuals.csv", csv.str());
  nlohmann::json rms = nlohmann::json::object();
  for (size_t f = 0; f < fig.forms.size(); ++f) rms[fig.forms[f]] = fig.rms[f];
  nlohmann::json titles = nlohmann::json::object();
  for (const std::string& f : fig.forms) titles[f] = f == "input" ? "input" : canonical_form_method_title(f);
  folder.write_json("pose_residuals.json", {{"a", fig.a},
                                            {"b", fig.b},
                                            {"class", fig.class_name},
                                            {"chosen_by", fig.chosen_by},
                                            {"forms", fig.forms},
                                            {"titles", titles},
                                            {"rms", rms}});
}

std::string label_of(const PoseInvarianceOptions& o) {
  return o.label.empty() ? "default" : o.label;
}

size_t count_form(const std::vector<PosePairRow>& rows, const std::string& form) {
  return static_cast<size_t>(
      std::count_if(rows.begin(), rows.end(), [&](const PosePairRow& r) { return r.form == form; }));
}
size_t count_form(const std::vector<PoseShapeRow>& rows, const std::string& form) {
  return static_cast<size_t>(
      std::count_if(rows.begin(), rows.end(), [&](const PoseShapeRow& r) { return r.form == form; }));
}

// With resampling: how the samples were carried to the remeshes, and how far they moved.
std::string located_markdown(const PoseInvarianceResult& result) {
  long samples = 0, relocated = 0, off_part = 0;
  double sum = 0, worst = 0;
  std::string worst_shape;
  std::ostringstream table;
  table << "| shape | samples | mean distance | max distance | relocated | off their part |\n"
           "|---|---:|---:|---:|---:|---:|\n";
  for (const PoseLocatedRow& r : result.located) {
    table << "| " << r.shape << " | " << r.samples << " | ";
    if (!r.remeshed) {
      table << "— | — | — | — |\n";  // its samples are its own vertices
      continue;
    }
    table << percent(r.mean_distance, 3) << " | " << percent(r.max_distance, 3) << " | " << r.relocated
          << " | " << r.off_part << " |\n";
    samples += r.samples;
    relocated += r.relocated;
    off_part += r.off_part;
    sum += r.mean_distance * r.samples;
    if (r.max_distance >= worst) {
      worst = r.max_distance;
      worst_shape = r.shape;
    }
  }
  std::ostringstream md;
  md << "Each ground-truth correspondence sample (a vertex of the input) was carried to its shape's "
        "remesh as the closest point of the remeshed surface, and each form's position of it interpolated "
        "there on the remesh's triangle (barycentric; core/locate_on_surface.h); poses that shared their "
        "faces "
        "are still paired vertex i with vertex i of the inputs. Edge stretch and geodesic stress are "
        "measured "
        "on the remeshes. Distance from the located points to the input vertices, over the input's "
        "bounding-box diagonal: mean "
     << percent(samples ? sum / static_cast<double>(samples) : NAN, 3) << ", largest " << percent(worst, 3)
     << (worst_shape.empty() ? "" : " (" + worst_shape + ")") << ". " << relocated + off_part << " of "
     << samples
     << " samples were closest to another part of the surface (a remeshed triangle whose corners lie, on "
        "the input, out of reach of the sample along it, as where an arm lies against the body: "
        "pipeline/remesh_samples.h); "
     << relocated << " of them were located on the closest triangle of their own part instead, " << off_part
     << " found none within reach and stayed.\n\n"
     << table.str();
  return md.str();
}

// The per-part section: the parts of each class, and per part the median RMS over pairs of each form.
std::string parts_markdown(const PoseInvarianceResult& result, const PoseInvarianceOptions& o) {
  std::ostringstream md;
  md << "\n## Where the pose stays: per part\n\n"
     << "Parts found on each class's first pose from its geometry alone (core/geodesic_parts.h): a centre "
        "(the "
        "vertex of least summed geodesic distance to "
     << o.part_finder.centre_sources
     << " evenly spaced vertices), the extremities (the local maxima of the geodesic distance from the "
        "centre whose topological persistence is at least "
     << fixed(o.part_finder.min_persistence, 2)
     << " of the largest distance: tips of limbs, not bumps), and each vertex in the part of its nearest "
        "extremity when nearer than "
     << fixed(o.part_finder.part_fraction, 2)
     << " of that extremity's distance to the centre, else in the core; carried to the other poses through "
        "the ground truth. Per part: the RMS of the residuals of its samples after the pair's whole-shape "
        "rigid fit (the fit of the pose RMS above, not one per part), over the mean diagonal; medians over "
        "pairs. The parts' mean squares, weighted by their samples, add up to the pose RMS². Parts are named "
        "by their extremity's vertex (0-based) on the class's first pose: which is a hand is not known. Per "
        "pair and form in `pose_parts.csv`.\n";
  const std::vector<std::string> forms = forms_of_run(o);
  for (const PoseClassParts& c : result.classes) {
    md << "\n**" << c.class_name << "** (parts found on " << c.shape << "): ";
    if (!c.problem.empty()) {
      md << "none (" << c.problem << ").\n";
      continue;
    }
    md << c.extremities.size() << " extremities";
    for (size_t e = 0; e < c.extremities.size(); ++e)
      md << (e ? "; " : ": ") << "part " << e + 1 << " at vertex " << c.extremities[e] << " (distance "
         << fixed(c.reach[e], 2) << ", persistence " << fixed(c.persistence[e], 2) << ")";
    md << "; centre: vertex " << c.centre << (c.repair_text.empty() ? "" : "; " + c.repair_text) << ".\n\n";
    md << "| part | samples per pair |";
    for (const std::string& f : forms)
      md << " " << (f == "input" ? "input" : canonical_form_method_title(f)) << " |";
    md << "\n| --- | --- |";
    for (size_t f = 0; f < forms.size(); ++f) md << " --- |";
    md << "\n";
    std::set<int> parts;
    for (const PosePartSummaryRow& r : result.part_summary)
      if (r.class_name == c.class_name) parts.insert(r.part);
    for (int part : parts) {
      std::string name =
          part < 0    ? "unassigned"
          : part == 0 ? "core"
                      : detail::concat("part ", part, " (extremity at vertex ",
                                       c.extremities[static_cast<size_t>(part - 1)], " of ", c.shape, ")");
      std::ostringstream cells;
      double samples = 0;
      for (const std::string& f : forms)
        for (const PosePartSummaryRow& r : result.part_summary)
          if (r.class_name == c.class_name && r.part == part && r.form == f) {
            cells << " " << percent(r.median_rms) << " |";
            if (f == "input") samples = r.median_samples;
          }
      md << "| " << name << " | " << fixed(samples, 0) << " |" << cells.str() << "\n";
    }
  }
  return md.str();
}

// The figure, or why there is none, and how to draw it.
std::string figure_markdown(const PoseInvarianceResult& result, const PoseInvarianceOptions& o) {
  const PoseFigurePair& fig = result.figure_pair;
  if (fig.a.empty()) return "";
  std::ostringstream md;
  md << "\n## Residuals of one pair\n\n";
  if (!result.figure.empty())
    md << "![residuals of " << fig.a << "-" << fig.b << "](" << result.figure << ")\n\n";
  else
    md << "No figure (" << result.figure_problem << ").\n\n";
  md << fig.a << " against " << fig.b << " (class " << fig.class_name << "), " << fig.chosen_by
     << ": each sample of " << fig.b
     << " at its input position, coloured by its residual after the pair's "
        "whole-shape rigid fit, in % of the mean diagonal, one colour scale for every panel. Pose RMS:";
  for (size_t f = 0; f < fig.forms.size(); ++f)
    md << (f ? "," : "") << " "
       << (fig.forms[f] == "input" ? "input" : canonical_form_method_title(fig.forms[f])) << " "
       << percent(fig.rms[f]);
  md << ". Data: `pose_residuals.csv`, `pose_residuals.json`; redraw with `scripts/python.sh "
        "experiments/plots/pose_figure.py "
     << o.out << "`.\n";
  return md.str();
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

  write_pairs_csv(folder, label_of(o), result);
  write_shapes_csv(folder, label_of(o), result);
  write_summary_csv(folder, label_of(o), result);
  if (o.parts) write_parts_csv(folder, label_of(o), result);
  if (!result.figure_pair.a.empty()) write_figure_data(folder, result.figure_pair);
  return result;
}

nlohmann::json pose_invariance_json(const PoseInvarianceResult& result) {
  nlohmann::json rows = nlohmann::json::array();
  for (const PoseSummaryRow& r : result.summary)
    rows.push_back({{"form", r.form},
                    {"class", r.class_name},
                    {"pairs", r.pairs},
                    {"median_rms", r.median_rms},
                    {"mean_rms", r.mean_rms},
                    {"median_input_rms", r.median_input_rms},
                    {"removed", r.removed},
                    {"mean_abs_stretch", r.mean_abs_stretch},
                    {"max_stretch", r.max_stretch},
                    {"stress", r.stress >= 0 ? nlohmann::json(r.stress) : nlohmann::json(nullptr)}});
  return {{"shapes", result.shapes.size()},
          {"pairs", result.pairs.size()},
          {"summary", rows},
          {"figure", result.figure},
          {"figure_problem", result.figure_problem},
          {"failures", shape_failures_json(result.failures)}};
}

std::string pose_invariance_markdown(const PoseInvarianceResult& result, const PoseInvarianceOptions& o) {
  std::ostringstream md;
  md << "# Pose invariance (" << label_of(o) << ")\n\n"
     << build_sentence() << "\n\n"
     << "Data: `" << o.data << "`, " << count_form(result.shapes, "input") << " shapes, "
     << count_form(result.pairs, "input") << " pairs of poses, up to " << o.samples
     << " ground-truth correspondences per pair"
     << (result.resampled ? detail::concat(", every shape remeshed to about ", o.resample.vertices,
                                           " vertices first (see Resampling below)")
                          : std::string())
     << ". Pose RMS: RMS distance between corresponding points of the "
        "two forms after the best rigid fit (reflections allowed), over the mean bounding-box diagonal; "
        "removed = 1 − form / input (medians over pairs). Stretch: edge length in the form / in the input, "
        "edges not torn; stress: against fast marching from "
     << o.stress_sources << " sources per shape (medians over shapes; max stretch: the worst edge).\n\n"
     << "| form | class | pairs | pose RMS (median) | mean | input | removed | mean \\|stretch−1\\| | max "
        "stretch | geodesic stress |\n| --- | --- | --- | --- | --- | --- | --- | --- | --- | --- |\n";
  for (const PoseSummaryRow& r : result.summary)
    md << "| " << r.form << " | " << r.class_name << " | " << r.pairs << " | " << percent(r.median_rms)
       << " | " << percent(r.mean_rms) << " | " << percent(r.median_input_rms) << " | "
       << percent(r.removed, 0) << " | " << (r.form == "input" ? "—" : fixed(r.mean_abs_stretch, 3)) << " | "
       << (r.form == "input" ? "—" : fixed(r.max_stretch, 2)) << " | " << fixed(measured_stress(r.stress), 3)
       << " |\n";
  if (o.parts && !result.classes.empty()) md << parts_markdown(result, o);
  md << figure_markdown(result, o);
  if (result.resampled)
    md << "\n## Resampling\n\n" << resampling_markdown(result.resampling) << "\n" << located_markdown(result);
  if (!result.failures.empty()) md << "\n" << shape_failures_markdown(result.failures);
  return md.str();
}

void write_pose_invariance_report(const PoseInvarianceResult& result, const PoseInvarianceOptions& options,
                                  const std::string& folder) {
  ExperimentFolder(folder).write_text("pose.md", pose_invariance_markdown(result, options));
}

void draw_pose_figure(PoseInvarianceResult& result, const PoseInvarianceOptions& options) {
  result.figure = "";
  if (result.figure_pair.a.empty()) {
    result.figure_problem = "no pair was measured";
  } else if (!options.figure) {
    result.figure_problem = "not requested (--no-draw)";
  } else {
    const FigureRun drawn = draw_figure("pose_figure.py", {options.out},
                                        ExperimentFolder(options.out).path("pose_residuals.png"));
    if (drawn.drawn) result.figure = "pose_residuals.png";
    result.figure_problem = drawn.problem;
  }
}

PoseInvarianceResult pose_experiment(const PoseInvarianceOptions& options) {
  PoseInvarianceResult result = run_pose_invariance(options);
  draw_pose_figure(result, options);
  write_pose_invariance_report(result, options, options.out);
  return result;
}

}  // namespace cshapes
