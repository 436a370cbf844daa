// cshapes.coulomb, classical_mds, smacof, canonical_form and the CanonicalForm they return: the drivers
// library's canonical forms (pipeline/canonical_forms.h) and the two MDS solvers on a distance matrix the
// caller has (canon/classical_mds.h, canon/smacof.h). Option names and defaults are the CLI's.
#include <pybind11/stl.h>

#include <algorithm>
#include <iterator>
#include <sstream>

#include "cshapes/canon/classical_mds.h"
#include "cshapes/canon/smacof.h"
#include "cshapes/support/error.h"
#include "cshapes/pipeline/canonical_form_methods.h"
#include "cshapes/pipeline/canonical_forms.h"
#include "cshapes/pipeline/mesh_report.h"
#include "python/bindings.h"
#include "python/convert.h"
#include "python/interrupt.h"
#include "python/kwargs.h"

namespace cshapes::python {

namespace {

// What every function here returns; arrays are owned by numpy.
struct PyCanonicalForm {
  py::object X;      // (n, 3) float64, the input's vertex order (NaN rows where valid is 0)
  py::object valid;  // (n,) float64: 1 for vertices in the form, 0 for vertices a repair dropped
  py::object torn;   // (n,) float64 (coulomb: 1 for vertices of torn edges) or None
  py::dict history;  // column name → (iterations,) float64
  int iterations = 0;
  py::object summary;  // dict: what `cshapes canon --json` prints for the method
  double seconds = 0;  // wall time: geodesics or graph set-up plus the solve
};

// The keywords of the `coulomb options` group (read_coulomb_options).
// clang-format off
const char* const kCoulombKeywords[] = {
    "scheme", "coulomb_start", "start_landmarks", "flatten", "step_rule", "step_gradient", "step_factor",
    "fixed_step", "coulomb_steps", "projection_steps", "projection", "l1_floor", "dilation", "tear_fraction",
    "tear_after", "tear_times", "tear_interval", "tear_guard", "coulomb_max_iterations", "coulomb_window",
    "coulomb_tolerance", "momentum", "coulomb_summation", "coulomb_accuracy", "coulomb_multiresolution_above",
    "coulomb_coarse_vertices", "coulomb_tear_rounds"};
// clang-format on

// Every keyword of canonical_form() but method, with the top-level CanonicalFormOptions fields it sets (as
// the CLI's options: cli/method_option_readers.cpp). Which methods read a keyword is not written here: a
// method reads it when it reads any of those fields (its registration's options_not_read, the table its cache
// key, the CLI's refusals and these use), and a keyword no reader of which is the method given is refused.
const std::vector<std::pair<std::string, std::vector<std::string>>>& keyword_fields() {
  static const std::vector<std::pair<std::string, std::vector<std::string>>> table = [] {
    std::vector<std::pair<std::string, std::vector<std::string>>> t;
    for (const char* name : kCoulombKeywords) t.push_back({name, {"coulomb"}});
    t.push_back({"geodesics", {"geodesics"}});
    for (const char* name : {"mds_solver", "landmarks"}) t.push_back({name, {"mds_solver"}});
    t.push_back({"fold_overstretch", {"mds_solver.fold_overstretch"}});
    for (const char* name : {"iters", "tolerance", "accelerate", "window"}) t.push_back({name, {"smacof"}});
    t.push_back({"init", {"smacof_init"}});
    t.push_back({"weights", {"smacof_weights"}});
    t.push_back({"eigenpairs", {"lbo", "diffusion"}});  // spectral-mds's eigenpairs are its basis
    for (const char* name : {"laplacian", "near_multiple_gap"})
      t.push_back({name, {"lbo", "diffusion", "spectral_mds"}});
    t.push_back({"diffusion_time", {"diffusion"}});
    for (const char* name : {"basis", "sources"}) t.push_back({name, {"spectral_mds"}});
    t.push_back({"knn", {"knn"}});
    t.push_back({"strict", {"strict"}});
    return t;
  }();
  return table;
}

bool reads(const CanonicalFormMethod& method, const char* field) {
  return reads_any_option(method, {field});
}

// The Laplace–Beltrami options (the `lbo options` and `diffusion options` groups of `cshapes canon`, and
// spectral-mds's), set in each spectral group of CanonicalFormOptions the method reads.
void read_spectral_options(Kwargs& k, const CanonicalFormMethod& method, CanonicalFormOptions& o) {
  std::vector<LaplaceBeltramiOptions*> eigenmaps;  // the groups whose eigenpairs are `eigenpairs`
  if (reads(method, "lbo")) eigenmaps.push_back(&o.lbo.laplacian);
  if (reads(method, "diffusion")) eigenmaps.push_back(&o.diffusion.laplacian);
  std::vector<LaplaceBeltramiOptions*> all = eigenmaps;
  if (reads(method, "spectral_mds")) all.push_back(&o.spectral_mds.laplacian);
  if (all.empty()) return;
  const LaplaceBeltramiOptions& first = *all.front();
  const std::string laplacian =
      k.text("laplacian", first.intrinsic_delaunay ? "intrinsic-delaunay" : "cotangent");
  if (laplacian != "intrinsic-delaunay" && laplacian != "cotangent")
    fail("laplacian: unknown '", laplacian, "'; known: intrinsic-delaunay, cotangent");
  if (!eigenmaps.empty()) {
    const int eigenpairs =
        k.int32("eigenpairs", eigenmaps.front()->eigenpairs, laplace_beltrami_limits::kEigenpairs);
    for (LaplaceBeltramiOptions* l : eigenmaps) l->eigenpairs = eigenpairs;
  }
  const double gap =
      k.number("near_multiple_gap", first.near_multiple_gap, laplace_beltrami_limits::kNearMultipleGap);
  for (LaplaceBeltramiOptions* l : all) {
    l->intrinsic_delaunay = laplacian == "intrinsic-delaunay";
    l->near_multiple_gap = gap;
  }
  if (reads(method, "diffusion"))
    o.diffusion.time = k.number("diffusion_time", o.diffusion.time, spectral_limits::kDiffusionTime);
  if (reads(method, "spectral_mds")) {
    LaplaceBeltramiOptions& l = o.spectral_mds.laplacian;
    l.eigenpairs = k.int32("basis", l.eigenpairs, laplace_beltrami_limits::kEigenpairs);
    o.spectral_mds.sources = k.integer("sources", o.spectral_mds.sources, 10, 100000);
    if (o.spectral_mds.sources < l.eigenpairs)
      fail("sources (", o.spectral_mds.sources, ") must be at least basis (", l.eigenpairs, ")");
  }
}

// The `coulomb options` group of `cshapes canon`, read from keywords, each checked against its library limit.
void read_coulomb_options(Kwargs& k, CanonicalFormOptions& o) {
  CoulombCanonOptions& c = o.coulomb;
  c.scheme = parse_coulomb_scheme(k.text("scheme", to_string(c.scheme)));
  c.start = parse_coulomb_start(k.text("coulomb_start", to_string(c.start)));
  c.start_landmarks =
      k.int32("start_landmarks", static_cast<int>(c.start_landmarks), coulomb_limits::kStartLandmarks);
  c.flatten = k.number("flatten", c.flatten, coulomb_limits::kFlatten);
  if (k.given("start_landmarks") && c.start != CoulombStart::LandmarkMds)
    fail("start_landmarks applies to coulomb_start='landmark-mds' only");
  c.step_rule = parse_coulomb_step_rule(k.text("step_rule", to_string(c.step_rule)));
  c.step_gradient = parse_step_gradient(k.text("step_gradient", to_string(c.step_gradient)));
  c.step_factor = k.number("step_factor", c.step_factor, coulomb_limits::kStepFactor);
  c.fixed_step = k.number("fixed_step", c.fixed_step, coulomb_limits::kFixedStep);
  c.coulomb_steps = k.int32("coulomb_steps", c.coulomb_steps, coulomb_limits::kCoulombSteps);
  c.projection.steps = k.int32("projection_steps", c.projection.steps, projection_limits::kSteps);
  c.projection.norm = parse_projection_norm(k.text("projection", to_string(c.projection.norm)));
  c.projection.l1_floor = k.number("l1_floor", c.projection.l1_floor, projection_limits::kL1Floor);
  c.projection.dilation = k.number("dilation", c.projection.dilation, projection_limits::kDilation);
  c.tear_fraction = k.number("tear_fraction", c.tear_fraction, coulomb_limits::kTearFraction);
  c.tear_after = k.int32("tear_after", c.tear_after, coulomb_limits::kTearAfter);
  c.tear_times = k.int32("tear_times", c.tear_times, coulomb_limits::kTearTimes);
  c.tear_interval = k.int32("tear_interval", c.tear_interval, coulomb_limits::kTearInterval);
  c.tear_guard = parse_tear_guard(k.text("tear_guard", to_string(c.tear_guard)));
  c.max_iterations = k.int32("coulomb_max_iterations", c.max_iterations, coulomb_limits::kMaxIterations);
  c.stop_window = k.int32("coulomb_window", c.stop_window, coulomb_limits::kWindow);
  c.stop_tolerance = k.number("coulomb_tolerance", c.stop_tolerance, coulomb_limits::kTolerance);
  c.momentum = k.number("momentum", c.momentum, coulomb_limits::kMomentum);
  c.energy.summation = parse_coulomb_summation(k.text("coulomb_summation", to_string(c.energy.summation)));
  c.energy.accuracy = k.number("coulomb_accuracy", c.energy.accuracy, coulomb_limits::kAccuracy);
  CoulombMultiresolutionOptions& mr = c.multiresolution;
  mr.above_vertices = k.int32("coulomb_multiresolution_above", static_cast<int>(mr.above_vertices),
                              coulomb_limits::kMultiresolutionAbove);
  mr.coarse_vertices =
      k.int32("coulomb_coarse_vertices", static_cast<int>(mr.coarse_vertices), coulomb_limits::kCoarseVertices);
  mr.tear_rounds = k.int32("coulomb_tear_rounds", mr.tear_rounds, coulomb_limits::kTearRounds);
  if (mr.above_vertices == 0)
    for (const char* fine : {"coulomb_coarse_vertices", "coulomb_tear_rounds"})
      if (k.given(fine)) fail(fine, " applies only with multiresolution (coulomb_multiresolution_above > 0)");
  // As the CLI: an option only another setting reads is refused rather than ignored.
  if (k.given("fixed_step") && c.step_rule != CoulombStepRule::Fixed)
    fail("fixed_step applies to step_rule='fixed' only");
  if (k.given("l1_floor") && c.projection.norm != ProjectionNorm::L1)
    fail("l1_floor applies to projection='l1' only");
  if (k.given("momentum") && c.scheme != CoulombScheme::Momentum)
    fail("momentum applies to scheme='momentum' only");
}

// SMACOF's solver options (both smacof() and canonical_form()).
void read_smacof_solver_options(Kwargs& k, SmacofOptions& s) {
  s.max_iterations = k.int32("iters", s.max_iterations, smacof_limits::kIterations);
  s.tolerance = k.number("tolerance", s.tolerance, smacof_limits::kTolerance);
  s.acceleration = parse_smacof_acceleration(k.text("accelerate", to_string(s.acceleration)));
  s.extrapolation_window = k.int32("window", s.extrapolation_window, smacof_limits::kWindow);
  if (k.given("window") && s.acceleration == SmacofAcceleration::None)
    fail("window applies to accelerate='rre' or 'mpe' only");
}

// The MDS solver of the methods that embed the geodesic matrix: full or landmark rows, and the landmark
// form's fold repair.
void read_mds_solver_options(Kwargs& k, MdsSolverOptions& m) {
  m.solver = parse_mds_solver(k.text("mds_solver", to_string(m.solver)));
  m.landmarks = k.integer("landmarks", m.landmarks, 4, 1000000);
  m.fold_overstretch = k.number("fold_overstretch", m.fold_overstretch, landmark_limits::kFoldOverstretch);
  if (m.fold_overstretch > 0 && m.fold_overstretch <= 1)
    fail("fold_overstretch: expected 0 (no repair) or a number above 1, got ", m.fold_overstretch);
  if (k.given("fold_overstretch") && m.solver == MdsSolver::Full)
    fail("fold_overstretch applies to mds_solver='landmarks' or 'auto' only");
}

// Refuses, by name, a keyword the method would ignore (as `cshapes canon --method` does), naming the methods
// that read it.
void refuse_unread_keywords(const Kwargs& k, const CanonicalFormMethod& method) {
  for (const auto& [name, fields] : keyword_fields())
    if (k.given(name) && !reads_any_option(method, fields))
      fail(name, " applies to method ", either_of(canonical_form_methods_reading(fields), "'"),
           " only, not '", method.name, "'");
}

PyCanonicalForm to_python(const CanonicalForm& form, const std::string& method) {
  PyCanonicalForm out;
  out.X = to_numpy(form.X);
  out.valid = to_numpy(form.valid);
  out.torn = form.torn.size() ? py::object(to_numpy(form.torn)) : py::object(py::none());
  for (size_t c = 0; c < form.history_columns.size(); ++c) {
    Eigen::VectorXd column(static_cast<Index>(form.history_rows.size()));
    for (size_t r = 0; r < form.history_rows.size(); ++r)
      column[static_cast<Index>(r)] = form.history_rows[r][c];
    out.history[form.history_columns[c].c_str()] = to_numpy(column);
  }
  out.iterations = form.iterations;
  out.summary = python::to_python(canonical_form_summary(form, method));
  out.seconds = form.precompute_seconds + form.solve_seconds;
  return out;
}

PyCanonicalForm canonical_form_py(const py::object& V, const py::object& F, const std::string& method,
                                  const py::kwargs& kwargs, const char* function) {
  const Mesh mesh = to_mesh(V, F);
  Kwargs k(kwargs, function);
  require_canonical_form_methods({method}, std::string(function) + "()");
  const CanonicalFormMethod& m = canonical_form_method(method);
  refuse_unread_keywords(k, m);
  CanonicalFormOptions o;
  o.method = method;
  o.knn.k = k.int32("knn", o.knn.k, kKnnLimit);  // every method: a point cloud's neighbourhood graph
  // As `cshapes canon --knn` on a mesh: the mesh's own edges are its graph, the keyword would be ignored.
  if (k.given("knn") && mesh.num_faces() > 0)
    fail("knn applies to point clouds (no faces) only; this mesh has ", mesh.num_faces(), " faces");
  if (reads(m, "coulomb")) read_coulomb_options(k, o);
  if (reads(m, "geodesics"))
    o.geodesics.method = parse_geodesic_method(k.text("geodesics", to_string(o.geodesics.method)));
  if (reads(m, "mds_solver")) read_mds_solver_options(k, o.mds_solver);
  if (reads(m, "smacof")) read_smacof_solver_options(k, o.smacof);
  if (reads(m, "smacof_init")) o.smacof_init = parse_smacof_init(k.text("init", to_string(o.smacof_init)));
  if (reads(m, "smacof_weights"))
    o.smacof_weights = parse_smacof_weights(k.text("weights", to_string(o.smacof_weights)));
  read_spectral_options(k, m, o);
  o.strict = k.flag("strict", false);
  k.done();
  o.name = std::string(function) + "() mesh";
  // Ctrl-C is heard at each iteration of the methods and every 64 sources of the geodesics
  // (python/interrupt.h).
  o.progress = stop_on_python_signals();
  CanonicalForm form;
  {
    Computing computing;
    form = canonical_form(mesh, o);
  }
  return to_python(form, method);
}

PyCanonicalForm classical_mds_py(const py::object& D_in, int dim) {
  CSHAPES_REQUIRE(dim >= 1 && dim <= 3,
                  "classical_mds(): dim: expected 1, 2 or 3 (the embedding is 3-D; "
                  "lower dimensions are its leading axes), got ",
                  dim);
  const Eigen::MatrixXd D = to_matrix(D_in, "D");
  ClassicalMdsResult r;
  ClassicalMdsOptions options;
  options.progress = stop_on_python_signals();
  {
    Computing computing;
    r = classical_mds(D, options);
  }
  PyCanonicalForm out = to_python(classical_mds_form(r), "cmds");
  out.X = to_numpy(Eigen::MatrixXd(r.X.leftCols(dim)));
  return out;
}

PyCanonicalForm smacof_py(const py::object& D_in, const py::object& X0_in, const py::kwargs& kwargs) {
  const DistanceMatrix D = to_distance_matrix(D_in, "D");
  Kwargs k(kwargs, "smacof");
  SmacofOptions so;
  read_smacof_solver_options(k, so);
  CSHAPES_REQUIRE(!k.given("init"), "smacof(): init: pass the start as X0 (None: classical MDS of D)");
  const py::object weights = k.object("weights");
  k.done();
  CSHAPES_REQUIRE(!py::isinstance<py::str>(weights),
                  "smacof(): weights: pass n vertex weights as an array (area weights need the mesh: use "
                  "canonical_form(V, F, method='smacof', weights='area'))");
  if (!weights.is_none()) so.vertex_weights = to_vector(weights, "weights");
  const bool have_start = !X0_in.is_none();
  Points X0 = have_start ? to_points(X0_in, "X0") : Points();
  so.progress = stop_on_python_signals();
  SmacofResult r;
  {
    Computing computing;
    r = have_start ? smacof(D, X0, so) : smacof(D, so);
  }
  return to_python(smacof_form(r, so), "smacof");
}

std::string coulomb_doc() {
  const CoulombCanonOptions c;
  const CanonicalFormOptions o;
  std::ostringstream d;
  d << "The Coulomb canonical form of a mesh (paper §2): electrostatic repulsion under edge-length "
       "constraints.\n\n"
       "V (n, 3) coordinates, F (m, 3) vertex indices (an empty F: a point cloud, joined by its kNN graph).\n"
       "Keywords, named as `cshapes canon --method coulomb` names them (defaults in brackets):\n"
    << "  scheme ['" << to_string(c.scheme) << "'] paper | momentum\n"
    << "  coulomb_start ['" << to_string(c.start) << "'] landmark-mds | input (the paper), start_landmarks ["
    << c.start_landmarks << "], flatten [" << c.flatten << "] (0: off, the paper)\n"
    << "  step_rule ['" << to_string(c.step_rule) << "'] max-edge | mean-edge | median-edge | fixed\n"
    << "  step_gradient ['" << to_string(c.step_gradient) << "'] max | mean\n"
    << "  step_factor [" << c.step_factor << "], fixed_step [" << c.fixed_step << "] (step_rule='fixed')\n"
    << "  coulomb_steps [" << c.coulomb_steps << "], projection_steps [" << c.projection.steps << "]\n"
    << "  projection ['" << to_string(c.projection.norm) << "'] l2 | l1, l1_floor [" << c.projection.l1_floor
    << "] (l1), dilation [" << c.projection.dilation << "]\n"
    << "  tear_fraction [" << c.tear_fraction << "], tear_after [" << c.tear_after << "], tear_times ["
    << c.tear_times << "], tear_interval [" << c.tear_interval << "], tear_guard ['"
    << to_string(c.tear_guard) << "'] connected | vertex\n"
    << "  coulomb_max_iterations [" << c.max_iterations << "], coulomb_window [" << c.stop_window
    << "], coulomb_tolerance [" << c.stop_tolerance << "]\n"
    << "  momentum [" << c.momentum << "] (scheme='momentum')\n"
    << "  coulomb_summation ['" << to_string(c.energy.summation) << "'] auto | direct | direct-float | fast, "
    << "coulomb_accuracy [" << c.energy.accuracy << "]\n"
    << "  coulomb_multiresolution_above [" << c.multiresolution.above_vertices
    << "] (0: never), coulomb_coarse_vertices [" << c.multiresolution.coarse_vertices
    << "], coulomb_tear_rounds [" << c.multiresolution.tear_rounds << "]\n"
    << "  knn [" << o.knn.k
    << "] (point clouds), strict [False] (refuse a mesh that needs repair)\n\n"
       "Returns a CanonicalForm: X (n, 3) in the input's vertex order and units, torn (n,) 1 at vertices of "
       "torn edges, history {energy, mean_violation, ...} per iteration, iterations, summary (dict), "
       "seconds.\n"
       "A mesh with several components or other defects is repaired for the method first (summary['repair'] "
       "says what); dropped vertices are NaN rows with valid = 0. The GIL is released while it runs.";
  return d.str();
}

// canonical_form()'s help: the methods' keywords, then which method reads which, from the same table the
// refusals use (keyword_fields and the registry).
std::string canonical_form_doc() {
  std::ostringstream d;
  d << R"(A canonical form by any method, as `cshapes canon --method M` computes it.

method: coulomb (keywords: see coulomb()), cmds or smacof (classical MDS / SMACOF of all-pairs geodesic
distances on the mesh; geodesics='heat' [as every command] | fmm [the paper's] | heat-cgal | exact | graph;
mds_solver ['auto'] | 'full' | 'landmarks' [L landmark rows above 12,000 vertices], landmarks [300]). smacof
also takes iters [300], tolerance [1e-5], init ['cmds'] | 'mesh', accelerate ['none'] | 'rre' | 'mpe', window
[6] (with rre/mpe), weights ['uniform'] | 'area', fold_overstretch [3.0] (landmarks: the fold repair; 0: off).
lbo (Laplace-Beltrami eigenmap, GPS) and diffusion (diffusion map at t = c/lambda_1) take laplacian
['intrinsic-delaunay'] | 'cotangent', eigenpairs [10], near_multiple_gap [0.02]; diffusion also
diffusion_time [1.0] (c). spectral-mds (Aflalo & Kimmel: MDS in the span of the first eigenfunctions) takes
laplacian, near_multiple_gap, basis [40], sources [120] and geodesics. Every method: knn [8] (point clouds:
the kNN graph standing in for the edges), strict [False].
A keyword the method does not read is refused, naming the methods that read it. Which reads which (the
method registry's table):
)";
  for (const CanonicalFormMethod& method : canonical_form_method_registry()) {
    std::string line;
    bool coulomb_keywords = false;
    for (const auto& [name, fields] : keyword_fields()) {
      if (!reads_any_option(method, fields)) continue;
      const bool coulomb = std::find(std::begin(kCoulombKeywords), std::end(kCoulombKeywords), name) !=
                           std::end(kCoulombKeywords);
      if (coulomb && coulomb_keywords) continue;
      line += (line.empty() ? "" : ", ") + (coulomb ? std::string("coulomb()'s keywords") : name);
      coulomb_keywords = coulomb_keywords || coulomb;
    }
    d << "  " << method.name << ": " << line << "\n";
  }
  d << "Returns a CanonicalForm.";
  return d.str();
}

}  // namespace

void bind_canon(py::module_& m) {
  py::class_<PyCanonicalForm>(m, "CanonicalForm",
                              "A canonical form: X (n, 3), valid (n,), torn (n,) or None, history (dict of "
                              "per-iteration columns), iterations, summary (dict), seconds")
      .def_readonly("X", &PyCanonicalForm::X)
      .def_readonly("valid", &PyCanonicalForm::valid)
      .def_readonly("torn", &PyCanonicalForm::torn)
      .def_readonly("history", &PyCanonicalForm::history)
      .def_readonly("iterations", &PyCanonicalForm::iterations)
      .def_readonly("summary", &PyCanonicalForm::summary)
      .def_readonly("seconds", &PyCanonicalForm::seconds)
      .def("__repr__", [](const PyCanonicalForm& f) {
        return "<cshapes.CanonicalForm: " + py::str(f.X.attr("shape")).cast<std::string>() + " points, " +
               std::to_string(f.iterations) + " iterations, " + std::to_string(f.seconds) + " s>";
      });
  m.def(
      "coulomb",
      [](const py::object& V, const py::object& F, const py::kwargs& kwargs) {
        return canonical_form_py(V, F, "coulomb", kwargs, "coulomb");
      },
      py::arg("V"), py::arg("F"), coulomb_doc().c_str());
  m.def(
      "canonical_form",
      [](const py::object& V, const py::object& F, const std::string& method, const py::kwargs& kwargs) {
        return canonical_form_py(V, F, method, kwargs, "canonical_form");
      },
      py::arg("V"), py::arg("F"), py::kw_only(), py::arg("method") = "coulomb", canonical_form_doc().c_str());
  m.def(
      "canonical_form_methods",
      [] {
        py::list methods;
        for (const CanonicalFormMethod& method : canonical_form_method_registry()) {
          py::dict d;
          d["name"] = method.name;
          d["title"] = method.title;
          d["uses_geodesic_matrix"] = method.uses_geodesic_matrix;
          methods.append(d);
        }
        return methods;
      },
      R"(The methods canonical_form() takes, in the library's order (pipeline/canonical_form_methods.h): a list
of dicts {name, title, uses_geodesic_matrix}; name is what method= takes, title the method's name in figures
and tables ('Coulomb', 'classical MDS', 'SMACOF').)");
  m.def("classical_mds", &classical_mds_py, py::arg("D"), py::arg("dim") = 3,
        R"(Classical MDS of an (n, n) distance matrix D (any real dtype; symmetric, zero diagonal).

Returns a CanonicalForm whose X is (n, dim), centred, in the units of D; dim 1..3 (the leading axes of the
3-D embedding). summary['classical_mds']: eigenvalues, most_negative_eigenvalue, explained_energy, ...
GIL released.)");
  m.def("smacof", &smacof_py, py::arg("D"), py::arg("X0") = py::none(),
        R"(SMACOF metric MDS of an (n, n) distance matrix D (stored as float32, as the library keeps them).

X0: (n, 3) start; None starts from classical MDS of D. Keywords (the CLI's): iters [300], tolerance
[1e-5], accelerate ['none'] | 'rre' | 'mpe', window [6] (rre/mpe), weights [None] or n positive vertex
weights (pair weights w_i w_j). Returns a CanonicalForm: X (n, 3), history (passes, normalized_stress,
extrapolated per iteration), iterations, summary['smacof'] {normalized_stress, stop_reason, ...}. GIL released.)");
}

}  // namespace cshapes::python
