// Methods cmds and smacof (pipeline/canonical_form_methods.h): MDS canonical forms (Elad & Kimmel) of a
// mesh's all-pairs geodesic distances, by classical MDS (canon/classical_mds.h) and SMACOF (canon/smacof.h).
#include <algorithm>
#include <cmath>
#include <nlohmann/json.hpp>

#include "cshapes/canon/form_quality.h"
#include "cshapes/canon/landmark_mds.h"
#include "cshapes/support/format.h"
#include "cshapes/support/error.h"
#include "cshapes/geodesics/heat_method.h"
#include "cshapes/mesh/mesh.h"
#include "cshapes/support/timing.h"
#include "cshapes/pipeline/canonical_form_methods.h"
#include "cshapes/pipeline/form_quality_json.h"

namespace cshapes {

namespace {

nlohmann::json cmds_summary(const ClassicalMdsResult& r) {
  return {{"eigenvalues", {r.eigenvalues[0], r.eigenvalues[1], r.eigenvalues[2]}},
          {"most_negative_eigenvalue", std::isfinite(r.most_negative_eigenvalue)
                                           ? nlohmann::json(r.most_negative_eigenvalue)
                                           : nlohmann::json(nullptr)},
          {"trace", r.trace},
          {"frobenius_squared", r.frobenius_squared},
          {"explained_energy", r.explained_energy},
          {"negative_mass_lower_bound", r.negative_mass_lower_bound},
          {"negative_energy_upper_bound", r.negative_energy_upper_bound},
          {"matrix_products", r.matrix_products},
          {"seconds", r.seconds}};
}

// SMACOF's result as a form's X, iterations and history.
void set_smacof_result(CanonicalForm& form, const SmacofResult& sr) {
  form.X = sr.X;
  form.iterations = sr.iterations;
  form.seconds_per_iteration = sr.seconds_per_iteration;
  form.history_columns = {"iteration", "passes", "normalized_stress", "extrapolated"};
  form.history_rows.clear();
  for (size_t k = 0; k < sr.stress_history.size(); ++k)
    form.history_rows.push_back({static_cast<double>(k), static_cast<double>(sr.passes_history[k]),
                                 sr.stress_history[k], sr.extrapolated_history[k] ? 1.0 : 0.0});
}

// SMACOF's kernel (canon/smacof.h) works in single precision on squared distances: beyond about 1e19 they
// overflow, below about 1e-19 they fall under FLT_MIN, and the form collapses to zeros (a mesh scaled by 1e20
// gave rows of zeros). Distances whose largest entry lies outside [1e-15, 1e15] (a margin for the squares'
// sums) are refused naming the mesh, as a scale the method cannot support.
void require_smacof_range(const Eigen::MatrixXf& distances, const std::string& name) {
  float largest = 0;  // of the finite entries: an infinite one is the distance checks' to name
  for (Index j = 0; j < distances.cols(); ++j)
    for (Index i = 0; i < distances.rows(); ++i)
      if (std::isfinite(distances(i, j))) largest = std::max(largest, distances(i, j));
  CSHAPES_REQUIRE(largest >= 1e-15f && largest <= 1e15f, name, ": smacof: the largest geodesic distance is ",
                  largest, ", outside [1e-15, 1e15], the single-precision range of the SMACOF kernel; scale "
                  "the mesh (its units are free) or use --method cmds");
}

// form_quality, and what only the iteration knows: a normalised stress that is not a number (the last
// entry of a SMACOF history) means the iteration broke down, however the coordinates look.
FormQuality mds_form_quality(const Mesh& mesh, const Edges& E, const CanonicalForm& form) {
  FormQuality quality = form_quality(mesh.V, E, form.X);
  const auto& columns = form.history_columns;
  const auto column = std::find(columns.begin(), columns.end(), "normalized_stress");
  if (column == columns.end() || form.history_rows.empty()) return quality;
  const double stress = form.history_rows.back()[static_cast<size_t>(column - columns.begin())];
  if (!std::isfinite(stress)) fail_form_quality(quality, "normalised stress " + std::to_string(stress));
  return quality;
}

nlohmann::json smacof_summary(const SmacofResult& sr, const SmacofOptions& so) {
  return {{"normalized_stress", sr.normalized_stress},
          {"initial_normalized_stress",
           sr.stress_history.empty() ? sr.normalized_stress : sr.stress_history.front()},
          {"iterations", sr.iterations},
          {"stop_reason", sr.stop_reason},
          {"acceleration", to_string(so.acceleration)},
          {"extrapolations_accepted", sr.extrapolations_accepted},
          {"extrapolations_rejected", sr.extrapolations_rejected},
          {"seconds", sr.seconds},
          {"seconds_per_iteration", sr.seconds_per_iteration}};
}

ClassicalMdsResult run_classical_mds(const DistanceMatrix& D, const CanonicalFormOptions& options) {
  ClassicalMdsResult r = classical_mds(D, options.cmds);
  say(options.note, "classical MDS: eigenvalues " + significant(r.eigenvalues[0]) + ", " +
                        significant(r.eigenvalues[1]) + ", " + significant(r.eigenvalues[2]) + "; 3-D keeps " +
                        significant(100 * r.explained_energy) +
                        "% of the spectrum's energy; most negative eigenvalue " +
                        significant(r.most_negative_eigenvalue) + " in " + significant(r.seconds) + " s");
  return r;
}

// The heat method's warning on a coarse mesh and the geodesic fallback, in the summary.
void note_geodesics(const Mesh& mesh, const CanonicalFormOptions& options, const CanonicalForm& form,
                    nlohmann::json& summary) {
  if (!form.geodesics_fallback.empty()) summary["geodesics_fallback"] = form.geodesics_fallback;
  if (form.geodesics_fallback.empty() && (options.geodesics.method == GeodesicMethod::Heat ||
                                          options.geodesics.method == GeodesicMethod::HeatCgal)) {
    const std::string warning = heat_method_warning(mesh);
    if (!warning.empty()) {
      summary["warning"] = warning;
      say(options.note, "warning: " + warning);
    }
  }
}

// Both methods from L landmark rows (canon/landmark_mds.h): landmark classical MDS, or SMACOF of the
// landmarks (from their classical MDS, or from the mesh) with the other points interpolated.
CanonicalForm landmark_mds_form(const Mesh& mesh, const CanonicalFormOptions& options, bool with_smacof) {
  CanonicalForm form;
  auto start = WallClock::now();
  const LandmarkGeodesics lg = canonical_form_landmark_geodesics(mesh, options, &form.geodesics_fallback);
  form.precompute_seconds = seconds_since(start);
  const Index L = lg.rows.rows(), n = lg.rows.cols();
  const double diagonal = finite_bbox_diagonal(mesh.V);
  say(options.note, "landmark geodesics: " + std::to_string(L) + " landmarks, covering radius " +
                        significant(lg.coverage_radius) +
                        (diagonal > 0 ? " (" + significant(100 * lg.coverage_radius / diagonal) +
                                            "% of the bbox diagonal)"
                                      : std::string()) +
                        ", in " + seconds_text(lg.seconds));
  nlohmann::json summary = nlohmann::json::object();
  note_geodesics(mesh, options, form, summary);
  summary["mds_solver"] = {{"solver", "landmarks"},
                           {"landmarks", L},
                           {"distance_entries", L * n},
                           {"coverage_radius", lg.coverage_radius},
                           {"geodesics_seconds", lg.seconds}};
  start = WallClock::now();
  LandmarkMdsResult r;
  if (!with_smacof) {
    r = landmark_classical_mds(lg.rows, lg.landmarks);
  } else {
    SmacofOptions so = options.smacof;
    if (!so.progress) so.progress = options.progress;
    if (options.smacof_weights == SmacofWeights::Area) so.vertex_weights = vertex_area_weights(mesh);
    Points landmark_start;
    if (options.smacof_init == SmacofInit::Mesh) {
      landmark_start.resize(L, 3);
      for (Index k = 0; k < L; ++k) landmark_start.row(k) = mesh.V.row(lg.landmarks[k]);
    }
    // The input's edge graph, so that points interpolated across a fold are placed again from their
    // neighbours (canon/landmark_mds.h, "Folds").
    LandmarkNeighbourGraph graph;
    if (options.mds_solver.fold_overstretch > 0) graph.edges = constraint_edges(mesh, options.knn);
    graph.overstretch = options.mds_solver.fold_overstretch;
    graph.lengths.resize(graph.edges.rows());
    for (Index e = 0; e < graph.edges.rows(); ++e)
      graph.lengths[e] = (mesh.V.row(graph.edges(e, 0)) - mesh.V.row(graph.edges(e, 1))).norm();
    require_smacof_range(lg.rows, options.name);
    r = landmark_smacof(lg.rows, lg.landmarks, so, options.mds_solver.interpolation_iterations,
                        landmark_start, graph);
    set_smacof_result(form, r.landmark_smacof);
    summary["smacof"] = smacof_summary(r.landmark_smacof, so);
    summary["smacof"]["init"] = to_string(options.smacof_init);
    summary["smacof"]["weights"] = to_string(options.smacof_weights);
    summary["smacof"]["start_point_stress"] = r.start_point_stress;
    summary["smacof"]["interpolated_point_stress"] = r.interpolated_point_stress;
    summary["smacof"]["fold_repair"] = {{"replaced_points", r.replaced_points},
                                        {"rounds", r.repair_rounds},
                                        {"overstretched_edges_left", r.overstretched_edges},
                                        {"kept", r.repair_kept}};
    if (r.replaced_points > 0)
      say(options.note, "landmark SMACOF: " + std::to_string(r.replaced_points) +
                            " points interpolated across a fold placed again from their neighbours (" +
                            std::to_string(r.repair_rounds) + " rounds, " +
                            std::to_string(r.overstretched_edges) + " edges still overstretched" +
                            (r.repair_kept ? ")" : "; not kept: no fewer than before)"));
    say(options.note, "landmark SMACOF: landmarks' normalised stress " +
                          significant(r.landmark_normalized_stress) + "; other points' stress " +
                          significant(r.start_point_stress) + " -> " + significant(r.interpolated_point_stress));
  }
  summary["landmark_mds"] = {{"eigenvalues", {r.eigenvalues[0], r.eigenvalues[1], r.eigenvalues[2]}},
                             {"explained_energy", r.explained_energy},
                             {"seconds", r.seconds}};
  form.X = std::move(r.X);
  form.solve_seconds = seconds_since(start);
  const FormQuality quality = mds_form_quality(mesh, constraint_edges(mesh, options.knn), form);
  say(options.note, "form quality " + quality.description);
  summary["form_quality"] = form_quality_json(quality);
  form.summary_json = summary.dump();
  return form;
}

// Both methods: the distances (given, or the geodesics computed here), classical MDS unless SMACOF starts
// from the mesh, then (with_smacof) SMACOF. Landmark rows instead of the matrix when the solver option says
// so and no matrix is given.
CanonicalForm mds_form(const Mesh& mesh, const CanonicalFormOptions& options,
                       const GivenDistances& given_distances, bool with_smacof) {
  const DistanceMatrix* given = given_distances.D;
  if (!given && mds_uses_landmarks(options, mesh.num_vertices()))
    return landmark_mds_form(mesh, options, with_smacof);
  CanonicalForm form;
  form.precompute_seconds = given_distances.seconds;
  form.geodesics_fallback = given ? given_distances.fallback : "";
  DistanceMatrix computed;
  if (!given) {
    auto start = WallClock::now();
    computed = canonical_form_geodesics(mesh, options, &form.geodesics_fallback);
    form.precompute_seconds = seconds_since(start);
    given = &computed;
  }
  CSHAPES_REQUIRE(given->rows() == mesh.num_vertices(), "MDS: distance matrix has ", given->rows(),
                  " rows for a mesh of ", mesh.num_vertices(), " vertices");
  auto start = WallClock::now();
  nlohmann::json summary = nlohmann::json::object();
  note_geodesics(mesh, options, form, summary);
  summary["mds_solver"] = {{"solver", "full"}, {"distance_entries", given->rows() * given->cols()}};
  const Edges E = constraint_edges(mesh, options.knn);
  Points X0;
  if (!with_smacof || options.smacof_init == SmacofInit::ClassicalMds) {
    ClassicalMdsResult cm = run_classical_mds(*given, options);
    summary["classical_mds"] = cmds_summary(cm);
    X0 = std::move(cm.X);
  } else {
    X0 = mesh.V;
  }
  if (!with_smacof) {
    form.X = std::move(X0);
  } else {
    SmacofOptions so = options.smacof;
    if (!so.progress) so.progress = options.progress;
    if (options.smacof_weights == SmacofWeights::Area) so.vertex_weights = vertex_area_weights(mesh);
    require_smacof_range(*given, options.name);
    SmacofResult sr = smacof(*given, X0, so);
    say(options.note, "SMACOF: normalised stress " + significant(sr.stress_history.front()) + " -> " +
                          significant(sr.normalized_stress) + " in " + std::to_string(sr.iterations) +
                          " iterations (" + sr.stop_reason + "), " + significant(sr.seconds_per_iteration) +
                          " s per iteration");
    set_smacof_result(form, sr);
    summary["smacof"] = smacof_summary(sr, so);
    summary["smacof"]["init"] = to_string(options.smacof_init);
    summary["smacof"]["weights"] = to_string(options.smacof_weights);
  }
  form.solve_seconds = seconds_since(start);
  const FormQuality quality = mds_form_quality(mesh, E, form);
  say(options.note, "form quality " + quality.description);
  summary["form_quality"] = form_quality_json(quality);
  form.summary_json = summary.dump();
  return form;
}

// The enum value named `name` among `names` (in the enum's order); throws naming the known ones.
template <class Enum>
Enum parse_named(const std::string& name, const std::vector<std::string>& names, const char* what) {
  for (size_t k = 0; k < names.size(); ++k)
    if (names[k] == name) return static_cast<Enum>(k);
  std::string known;
  for (const std::string& n : names) known += (known.empty() ? "" : ", ") + n;
  fail(what, ": unknown '", name, "'; known: ", known);
}

const std::string& name_of(size_t index, const std::vector<std::string>& names) {
  CSHAPES_REQUIRE(index < names.size(), "an enum value outside its names");
  return names[index];
}

CanonicalForm cmds_compute(const Mesh& mesh, const CanonicalFormOptions& options,
                           const GivenDistances& given) {
  return mds_form(mesh, options, given, /*with_smacof=*/false);
}

CanonicalForm smacof_compute(const Mesh& mesh, const CanonicalFormOptions& options,
                             const GivenDistances& given) {
  return mds_form(mesh, options, given, /*with_smacof=*/true);
}

}  // namespace

// Function-local statics: the CLI's option defaults may ask during static initialisation.
const std::vector<std::string>& smacof_init_names() {
  static const std::vector<std::string> names = {"cmds", "mesh"};  // SmacofInit's order
  return names;
}
const std::vector<std::string>& smacof_weights_names() {
  static const std::vector<std::string> names = {"uniform", "area"};  // SmacofWeights's order
  return names;
}
SmacofInit parse_smacof_init(const std::string& name) {
  return parse_named<SmacofInit>(name, smacof_init_names(), "smacof init");
}
SmacofWeights parse_smacof_weights(const std::string& name) {
  return parse_named<SmacofWeights>(name, smacof_weights_names(), "smacof weights");
}
std::string to_string(SmacofInit init) {
  return name_of(static_cast<size_t>(init), smacof_init_names());
}
std::string to_string(SmacofWeights weights) {
  return name_of(static_cast<size_t>(weights), smacof_weights_names());
}

CanonicalForm classical_mds_form(const ClassicalMdsResult& r) {
  CanonicalForm form;
  form.X = r.X;
  form.valid = Eigen::VectorXd::Ones(r.X.rows());
  form.solve_seconds = r.seconds;
  form.summary_json = nlohmann::json{{"classical_mds", cmds_summary(r)}}.dump();
  return form;
}

CanonicalForm smacof_form(const SmacofResult& r, const SmacofOptions& options) {
  CanonicalForm form;
  set_smacof_result(form, r);
  form.valid = Eigen::VectorXd::Ones(r.X.rows());
  form.solve_seconds = r.seconds;
  form.summary_json = nlohmann::json{{"smacof", smacof_summary(r, options)}}.dump();
  return form;
}

CanonicalFormMethod cmds_method() {
  CanonicalFormMethod m;
  m.name = "cmds";
  m.title = "classical MDS";
  m.requirements = MeshRequirements::manifold_surface();
  m.repair_purpose = "cmds (its geodesics need one manifold component without zero-area faces)";
  m.uses_geodesic_matrix = true;
  // The fold repair is SMACOF's (on landmark rows): classical MDS interpolates without one.
  m.options_not_read = {"coulomb", "smacof",    "smacof_init",  "smacof_weights",
                        "lbo",     "diffusion", "spectral_mds", "mds_solver.fold_overstretch"};
  m.compute = cmds_compute;
  return m;
}

CanonicalFormMethod smacof_method() {
  CanonicalFormMethod m;
  m.name = "smacof";
  m.title = "SMACOF";
  m.requirements = MeshRequirements::manifold_surface();
  m.repair_purpose = "smacof (its geodesics need one manifold component without zero-area faces)";
  m.uses_geodesic_matrix = true;
  m.options_not_read = {"coulomb", "lbo", "diffusion", "spectral_mds"};  // it reads cmds: classical MDS is its start
  m.has_history = true;
  m.compute = smacof_compute;
  return m;
}

}  // namespace cshapes
