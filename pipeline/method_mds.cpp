// Methods cmds and smacof (pipeline/canonical_form_methods.h): MDS canonical forms (Elad & Kimmel) of a
// mesh's all-pairs geodesic distances, by classical MDS (canon/classical_mds.h) and SMACOF (canon/smacof.h).
#include <algorithm>
#include <cmath>
#include <nlohmann/json.hpp>

#include "cshapes/canon/landmark_mds.h"
#include "cshapes/support/format.h"
#include "cshapes/support/error.h"
#include "cshapes/geodesics/heat_method.h"
#include "cshapes/mesh/mesh.h"
#include "cshapes/support/timing.h"
#include "cshapes/pipeline/canonical_form_methods.h"

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

// What only the iteration knows for the form's quality check: a normalised stress that is not a number (the
// last entry of a SMACOF history) means the iteration broke down, however the coordinates look. "" otherwise.
std::string smacof_breakdown(const CanonicalForm& form) {
  const auto& columns = form.history_columns;
  const auto column = std::find(columns.begin(), columns.end(), "normalized_stress");
  if (column == columns.end() || form.history_rows.empty()) return "";
  const double stress = form.history_rows.back()[static_cast<size_t>(column - columns.begin())];
  return std::isfinite(stress) ? "" : "normalised stress " + std::to_string(stress);
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
      say(options.note, "landmark SMACOF: " + counted(r.replaced_points, "point") +
                            " interpolated across a fold placed again from their neighbours (" +
                            counted(r.repair_rounds, "round") + ", " +
                            counted(r.overstretched_edges, "edge") + " still overstretched" +
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
  form.breakdown = smacof_breakdown(form);
  form.details = std::move(summary);
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
                          significant(sr.normalized_stress) + " in " + counted(sr.iterations, "iteration") +
                          " (" + sr.stop_reason + "), " + duration_text(sr.seconds_per_iteration) +
                          " per iteration");
    set_smacof_result(form, sr);
    summary["smacof"] = smacof_summary(sr, so);
    summary["smacof"]["init"] = to_string(options.smacof_init);
    summary["smacof"]["weights"] = to_string(options.smacof_weights);
  }
  form.solve_seconds = seconds_since(start);
  form.breakdown = smacof_breakdown(form);
  form.details = std::move(summary);
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

using Ref = CanonicalFormOptions&;

// --distances: the matrix itself, read by `cshapes canon` only (Python's canonical_form() takes no file).
MethodOption distances_option() {
  MethodOption o = option_of("distances", MethodOption::Type::Path,
                             "read the n×n distance matrix (.bin, see `cshapes geodesics`) instead",
                             {"distances_file"});
  o.get = [](const CanonicalFormOptions& c) { return OptionValue(c.distances_file); };
  o.set = [](CanonicalFormOptions& c, const OptionValue& v) { c.distances_file = std::get<std::string>(v); };
  o.python = false;
  return o;
}

// The options cmds and smacof share: the geodesic matrix (computed or read) and full or landmark MDS of it.
std::vector<MethodOption> mds_options() {
  std::vector<MethodOption> o = {geodesics_option(), distances_option()};
  o.push_back(choice_option<MdsSolver>(
      "mds_solver",
      "full (the n×n geodesic matrix), landmarks (L rows: landmark MDS, SMACOF on the landmarks), or auto "
      "(landmarks above 12,000 vertices or when the matrix would take more than half the free memory)",
      mds_solver_names(), {"mds_solver"}, [](Ref c) -> MdsSolver& { return c.mds_solver.solver; }, to_string,
      parse_mds_solver));
  o.push_back(integer_option<Index>(
      "mds_landmarks", "landmarks L for --mds-solver landmarks|auto (farthest-point sampling)",
      landmark_limits::kLandmarks, {"mds_solver"}, [](Ref c) -> Index& { return c.mds_solver.landmarks; }));
  o.back().applies_when = MethodOption::Condition{"mds_solver", {"landmarks", "auto"}, ""};
  return o;
}

std::vector<MethodOption> smacof_options() {
  std::vector<MethodOption> o = mds_options();
  const std::vector<std::string> f = {"smacof"};
  o.push_back(integer_option<int>("smacof_max_iterations", "maximum iterations (passes over D)",
                                  smacof_limits::kIterations, f,
                                  [](Ref c) -> int& { return c.smacof.max_iterations; }));
  o.push_back(number_option("smacof_tolerance", "stop when the relative stress decrease is below this",
                            smacof_limits::kTolerance, f,
                            [](Ref c) -> double& { return c.smacof.tolerance; }));
  o.push_back(choice_option<SmacofInit>("init", "initial configuration: cmds (classical MDS) or mesh",
                                        smacof_init_names(), {"smacof_init"},
                                        [](Ref c) -> SmacofInit& { return c.smacof_init; }, to_string,
                                        parse_smacof_init));
  o.push_back(choice_option<SmacofAcceleration>(
      "accelerate", "vector extrapolation: none, rre or mpe", {"none", "rre", "mpe"}, f,
      [](Ref c) -> SmacofAcceleration& { return c.smacof.acceleration; }, to_string, parse_smacof_acceleration));
  o.push_back(integer_option<int>("smacof_window", "Guttman steps per extrapolation", smacof_limits::kWindow,
                                  f, [](Ref c) -> int& { return c.smacof.extrapolation_window; }));
  o.back().applies_when = MethodOption::Condition{"accelerate", {"rre", "mpe"}, ""};
  o.push_back(choice_option<SmacofWeights>("weights", "pair weights w_i*w_j from uniform or area (vertex areas)",
                                           smacof_weights_names(), {"smacof_weights"},
                                           [](Ref c) -> SmacofWeights& { return c.smacof_weights; }, to_string,
                                           parse_smacof_weights));
  o.push_back(number_option("fold_overstretch",
                            "on landmarks: points on edges longer than this × their input length (or the mean "
                            "edge) are placed again beside their neighbours; 0: no repair",
                            landmark_limits::kFoldOverstretch, {"mds_solver"},
                            [](Ref c) -> double& { return c.mds_solver.fold_overstretch; }));
  o.back().applies_when = MethodOption::Condition{"mds_solver", {"landmarks", "auto"}, ""};
  return o;
}

// What the options of cmds and smacof cannot say alone.
void check_mds(const CanonicalFormOptions&, const OptionFace& face) {
  const std::string geodesics = face.name(geodesics_option()), distances = face.name(distances_option());
  if (face.given("geodesics") && face.given("distances"))
    fail(geodesics, " and ", distances, " exclude each other (", distances, " reads the distances instead)");
  if (face.given("distances") && !face.single_mesh)
    fail(distances, ": only `cshapes canon` reads a precomputed distance matrix (here every shape needs its own)");
}

void check_smacof(const CanonicalFormOptions& o, const OptionFace& face) {
  check_mds(o, face);
  const double fold = o.mds_solver.fold_overstretch;
  if (fold > 0 && fold <= 1)
    fail(face.cli ? "--fold-overstretch" : "fold_overstretch", ": expected 0 (no repair) or a number above 1, got ",
         format_limit_number(fold));
  if (o.smacof_init != SmacofInit::ClassicalMds && !face.single_mesh)
    fail(face.cli ? "--init " : "init=", to_string(o.smacof_init),
         ": only `cshapes canon` starts SMACOF from the mesh; here it starts from classical MDS");
  if (o.smacof_weights != SmacofWeights::Uniform && !face.single_mesh)
    fail(face.cli ? "--weights " : "weights=", to_string(o.smacof_weights),
         ": only `cshapes canon` weights SMACOF by vertex areas; here weights are uniform");
}

}  // namespace

MethodOption geodesics_option() {
  return choice_option<GeodesicMethod>(
      "geodesics",
      "geodesic distances to embed (heat, heat-cgal, fmm, exact, graph); default: heat in every command and "
      "in Python (fmm is the paper's)",
      {"heat", "heat-cgal", "fmm", "exact", "graph"}, {"geodesics"},
      [](CanonicalFormOptions& c) -> GeodesicMethod& { return c.geodesics.method; }, to_string,
      parse_geodesic_method);
}

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
  form.details = {{"classical_mds", cmds_summary(r)}};
  return form;
}

CanonicalForm smacof_form(const SmacofResult& r, const SmacofOptions& options) {
  CanonicalForm form;
  set_smacof_result(form, r);
  form.valid = Eigen::VectorXd::Ones(r.X.rows());
  form.solve_seconds = r.seconds;
  form.details = {{"smacof", smacof_summary(r, options)}};
  return form;
}

CanonicalFormMethod cmds_method() {
  CanonicalFormMethod m;
  m.name = "cmds";
  m.results_version = 2;  // 2: landmarks sampled from the central vertex, ties by position (not from vertex 0)
  m.title = "classical MDS";
  m.summary = "classical MDS (Young-Householder) of all-pairs geodesic distances";
  m.requirements = MeshRequirements::manifold_surface();
  m.repair_purpose = "cmds (its geodesics need one manifold component without zero-area faces)";
  m.uses_geodesic_matrix = true;
  m.options = mds_options();  // not fold_overstretch: the fold repair is SMACOF's (classical MDS has none)
  m.reads = {"geodesics", "cmds", "mds_solver", "distances_file"};
  m.check = check_mds;
  m.compute = cmds_compute;
  return m;
}

CanonicalFormMethod smacof_method() {
  CanonicalFormMethod m;
  m.name = "smacof";
  m.results_version = 2;  // 2: landmarks sampled from the central vertex, ties by position (not from vertex 0)
  m.title = "SMACOF";
  m.summary = "SMACOF metric MDS (Guttman transforms) of all-pairs geodesic distances";
  m.requirements = MeshRequirements::manifold_surface();
  m.repair_purpose = "smacof (its geodesics need one manifold component without zero-area faces)";
  m.uses_geodesic_matrix = true;
  m.options = smacof_options();
  // cmds: classical MDS is its start.
  m.reads = {"geodesics", "cmds", "smacof", "smacof_init", "smacof_weights", "mds_solver", "distances_file"};
  m.check = check_smacof;
  m.has_history = true;
  m.compute = smacof_compute;
  return m;
}

}  // namespace cshapes
