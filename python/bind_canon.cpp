// cshapes.coulomb, classical_mds, smacof, canonical_form and the CanonicalForm they return: the drivers
// library's canonical forms (pipeline/canonical_forms.h) and the two MDS solvers on a distance matrix the
// caller has (canon/classical_mds.h, canon/smacof.h). Option names and defaults are the CLI's.
#include <pybind11/stl.h>

#include <algorithm>
#include <iterator>

#include "cshapes/canon/classical_mds.h"
#include "cshapes/canon/smacof.h"
#include "cshapes/pipeline/canonical_form_methods.h"
#include "cshapes/pipeline/canonical_forms.h"
#include "cshapes/pipeline/mesh_report.h"
#include "cshapes/pipeline/method_options.h"
#include "cshapes/support/error.h"
#include "cshapes/support/format.h"
#include "python/bindings.h"
#include "python/convert.h"
#include "python/interrupt.h"
#include "python/kwargs.h"
#include "python/method_argument.h"
#include "python/progress.h"

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
  std::string method;  // the method's name ('coulomb', 'cmds', ...; a method from outside: its name)
};

// "<cshapes.CanonicalForm: coulomb, 5,000 points, 50 iterations, 0.615 s>": what a person reads first; the
// arrays and the full precision are in the attributes.
std::string form_repr(const PyCanonicalForm& f) {
  const py::tuple shape = f.X.attr("shape");
  const long long n = shape[0].cast<long long>(), dim = py::len(shape) > 1 ? shape[1].cast<long long>() : 1;
  const long long kept = py::int_(f.valid.attr("sum")()).cast<long long>();
  std::string points = kept == n ? counted(n, "point") : grouped(kept) + " of " + counted(n, "point");
  if (dim != 3) points += " in " + std::to_string(dim) + "-D";
  return "<cshapes.CanonicalForm: " + (f.method.empty() ? "" : f.method + ", ") + points + ", " +
         counted(f.iterations, "iteration") + ", " + seconds_text(f.seconds) + ">";
}

OptionFace python_face(const Kwargs& k) {
  OptionFace face;
  face.cli = false;
  face.single_mesh = true;
  face.given = [&k](const std::string& name) { return k.given(name); };
  return face;
}

// One method option's keyword (given), checked against its limit or choices as the CLI checks it.
OptionValue read_keyword(Kwargs& k, const MethodOption& option, const CanonicalFormOptions& o) {
  const OptionValue fallback = option.get(o);
  switch (option.type) {
    case MethodOption::Type::Integer:
      return OptionValue(static_cast<long long>(
          k.int32(option.name, static_cast<int>(std::get<long long>(fallback)), *option.limit)));
    case MethodOption::Type::Number: return OptionValue(k.number(option.name, std::get<double>(fallback), *option.limit));
    case MethodOption::Type::Choice: {
      const std::string value = k.text(option.name, std::get<std::string>(fallback));
      if (std::find(option.choices.begin(), option.choices.end(), value) == option.choices.end()) {
        std::string known;
        for (const std::string& c : option.choices) known += (known.empty() ? "" : ", ") + c;
        fail(option.name, ": unknown '", value, "'; known: ", known);
      }
      return OptionValue(value);
    }
    case MethodOption::Type::Path: return OptionValue(k.text(option.name, std::get<std::string>(fallback)));
  }
  return fallback;
}

// One option's keyword read (even when absent: Kwargs::done() then lists it as known) and, when given, set.
void read_and_set(Kwargs& k, const MethodOption& option, CanonicalFormOptions& o) {
  const bool given = k.given(option.name);
  const OptionValue value = read_keyword(k, option, o);
  if (given) option.set(o, value);
}

// The keywords of `method`'s options (its registration's list, pipeline/canonical_form_methods.h), as
// `cshapes canon --method` reads its options: one the method does not list is refused naming the methods
// that do; each given is checked and set in `o`; then the conditions and the method's own checks.
void read_method_keywords(Kwargs& k, const CanonicalFormMethod& method, CanonicalFormOptions& o) {
  const OptionFace face = python_face(k);
  refuse_options_not_read({method.name}, face);
  for (const MethodOption& option : method.options)
    if (option.python) read_and_set(k, option, o);
  check_method_options({method.name}, o, face);
}

// The options named (each a registered method's) read from keywords into `o`, with their conditions: what
// smacof() shares with method smacof.
void read_named_keywords(Kwargs& k, const std::vector<std::string>& names, CanonicalFormOptions& o) {
  const std::vector<const MethodOption*> all = all_method_options();
  for (const MethodOption* option : all)
    if (std::find(names.begin(), names.end(), option->name) != names.end()) read_and_set(k, *option, o);
  for (const MethodOption* option : all)
    if (std::find(names.begin(), names.end(), option->name) != names.end())
      check_applies_when(*option, all, o, python_face(k));
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
  out.method = method;
  return out;
}

// method: a name, "NAME=cmd:COMMAND" / "NAME=forms:DIR", a function fn(V, F) -> X (named by its __name__)
// or a pair (NAME, fn): a method from outside is registered for this call only (python/method_argument.h).
PyCanonicalForm canonical_form_py(const py::object& V, const py::object& F, const py::object& method_in,
                                  const py::kwargs& kwargs, const char* function) {
  const Mesh mesh = to_mesh(V, F);
  Kwargs k(kwargs, function);
  MethodArgument outside;  // released with the GIL held, at the end of this call
  std::string method;
  if (py::isinstance<py::str>(method_in) && !is_outside_method_item(method_in.cast<std::string>())) {
    method = method_in.cast<std::string>();
  } else {
    py::object item = method_in;
    if (PyCallable_Check(item.ptr())) {
      std::string name = py::str(py::getattr(item, "__name__", py::str("function"))).cast<std::string>();
      const bool valid = !name.empty() && std::all_of(name.begin(), name.end(), [](char c) {
        return std::isalnum(static_cast<unsigned char>(c)) || c == '-' || c == '_';
      });
      item = py::make_tuple(valid ? name : std::string("function"), item);
    }
    CSHAPES_REQUIRE(py::isinstance<py::str>(item) || py::isinstance<py::tuple>(item), function,
                    "(): method: expected a method's name, 'NAME=cmd:COMMAND', 'NAME=forms:DIR', a function "
                    "fn(V, F) -> X or a pair (name, fn), got ",
                    std::string(py::str(method_in.get_type().attr("__name__"))));
    py::list items;
    items.append(item);
    outside = method_argument(items, function, k);
    method = outside.names.front();
  }
  require_canonical_form_methods({method}, std::string(function) + "()");
  const CanonicalFormMethod& m = canonical_form_method(method);
  CanonicalFormOptions o;
  o.method = method;
  o.knn.k = k.int32("knn", o.knn.k, kKnnLimit);  // every method: a point cloud's neighbourhood graph
  // As `cshapes canon --knn` on a mesh: the mesh's own edges are its graph, the keyword would be ignored.
  if (k.given("knn") && mesh.num_faces() > 0)
    fail("knn applies to point clouds (no faces) only; this mesh has ", mesh.num_faces(), " faces");
  read_method_keywords(k, m, o);
  o.strict = k.flag("strict", false);
  const PythonProgress progress(k.object("progress"), function);
  k.done();
  o.name = std::string(function) + "() mesh";
  // Reports (and Ctrl-C) at each iteration of the methods and every 64 sources of the geodesics
  // (python/progress.h).
  o.progress = progress.fn();
  const CanonicalForm form = progress.run([&] { return canonical_form(mesh, o); });
  return to_python(form, method);
}

PyCanonicalForm classical_mds_py(const py::object& D_in, int dim, const py::object& progress_in) {
  CSHAPES_REQUIRE(dim >= 1 && dim <= 3,
                  "classical_mds(): dim: expected 1, 2 or 3 (the embedding is 3-D; "
                  "lower dimensions are its leading axes), got ",
                  dim);
  const Eigen::MatrixXd D = to_matrix(D_in, "D");
  ClassicalMdsOptions options;
  const PythonProgress progress(progress_in, "classical_mds");
  options.progress = progress.fn();
  const ClassicalMdsResult r = progress.run([&] { return classical_mds(D, options); });
  PyCanonicalForm out = to_python(classical_mds_form(r), "cmds");
  out.X = to_numpy(Eigen::MatrixXd(r.X.leftCols(dim)));
  return out;
}

PyCanonicalForm smacof_py(const py::object& D_in, const py::object& X0_in, const py::kwargs& kwargs) {
  const DistanceMatrix D = to_distance_matrix(D_in, "D");
  Kwargs k(kwargs, "smacof");
  CanonicalFormOptions o;
  read_named_keywords(k, {"smacof_max_iterations", "smacof_tolerance", "accelerate", "smacof_window"}, o);
  SmacofOptions so = o.smacof;
  CSHAPES_REQUIRE(!k.given("init"), "smacof(): init: pass the start as X0 (None: classical MDS of D)");
  const py::object weights = k.object("weights");
  const PythonProgress progress(k.object("progress"), "smacof");
  k.done();
  CSHAPES_REQUIRE(!py::isinstance<py::str>(weights),
                  "smacof(): weights: pass n vertex weights as an array (area weights need the mesh: use "
                  "canonical_form(V, F, method='smacof', weights='area'))");
  if (!weights.is_none()) so.vertex_weights = to_vector(weights, "weights");
  const bool have_start = !X0_in.is_none();
  Points X0 = have_start ? to_points(X0_in, "X0") : Points();
  so.progress = progress.fn();
  const SmacofResult r = progress.run([&] { return have_start ? smacof(D, X0, so) : smacof(D, so); });
  return to_python(smacof_form(r, so), "smacof");
}

// The options of every registered method, for scripts/make_stub.py and the docs: name, type, default,
// choices, limit, help, the methods that read it.
py::list method_options_py() {
  py::list out;
  for (const MethodOption* option : all_method_options()) {
    if (!option->python) continue;
    py::dict d;
    d["name"] = option->name;
    d["flag"] = cli_flag(*option);
    const char* types[] = {"int", "float", "str", "str"};
    d["type"] = types[static_cast<int>(option->type)];
    const OptionValue fallback = option_default(*option);
    if (const long long* i = std::get_if<long long>(&fallback)) d["default"] = *i;
    else if (const double* x = std::get_if<double>(&fallback)) d["default"] = *x;
    else d["default"] = option_text(fallback);
    d["choices"] = option->choices;
    d["limit"] = option->limit ? py::object(py::str(option->limit->describe())) : py::object(py::none());
    d["help"] = option->help;
    d["methods"] = canonical_form_methods_reading(option->name);
    out.append(d);
  }
  return out;
}

}  // namespace

void bind_canon(py::module_& m) {
  // The docstrings here are one line each: cshapes/_api.py gives the Python functions their signatures and
  // numpy-style documentation, the keywords' from the methods' own option declarations (method_options()).
  py::class_<PyCanonicalForm>(m, "CanonicalForm",
                              "A canonical form: X (n, 3), valid (n,), torn (n,) or None, history (dict of "
                              "per-iteration columns), iterations, summary (dict), seconds, method")
      .def_readonly("X", &PyCanonicalForm::X,
                    "(n, 3) float64: the form, in the input's vertex order and units "
                    "(NaN rows where valid is 0)")
      .def_readonly("valid", &PyCanonicalForm::valid,
                    "(n,) float64: 1 for vertices in the form, 0 for vertices a repair dropped")
      .def_readonly("torn", &PyCanonicalForm::torn,
                    "(n,) float64, 1 at vertices of torn edges (coulomb), or None")
      .def_readonly("history", &PyCanonicalForm::history,
                    "dict: column name -> (iterations,) float64 (energy, mean_violation, ... per iteration)")
      .def_readonly("iterations", &PyCanonicalForm::iterations, "iterations the solver ran")
      .def_readonly("summary", &PyCanonicalForm::summary, "dict: what `cshapes canon --json` prints")
      .def_readonly("seconds", &PyCanonicalForm::seconds, "wall time in seconds: set-up plus the solve")
      .def_readonly("method", &PyCanonicalForm::method, "the method's name ('coulomb', 'cmds', ...)")
      .def("__repr__", &form_repr);
  m.def(
      "coulomb",
      [](const py::object& V, const py::object& F, const py::kwargs& kwargs) {
        return canonical_form_py(V, F, py::str("coulomb"), kwargs, "coulomb");
      },
      py::arg("V"), py::arg("F"), "The Coulomb canonical form of a mesh: see help(cshapes.coulomb).");
  m.def(
      "canonical_form",
      [](const py::object& V, const py::object& F, const py::object& method, const py::kwargs& kwargs) {
        return canonical_form_py(V, F, method, kwargs, "canonical_form");
      },
      py::arg("V"), py::arg("F"), py::kw_only(), py::arg("method") = "coulomb",
      "A canonical form by any method: see help(cshapes.canonical_form).");
  m.def(
      "canonical_form_methods",
      [] {
        py::list methods;
        for (const CanonicalFormMethod& method : canonical_form_method_registry()) {
          py::dict d;
          d["name"] = method.name;
          d["title"] = method.title;
          d["summary"] = method.summary;
          d["uses_geodesic_matrix"] = method.uses_geodesic_matrix;
          std::vector<std::string> keywords;
          for (const MethodOption& option : method.options)
            if (option.python) keywords.push_back(option.name);
          d["keywords"] = keywords;
          methods.append(d);
        }
        return methods;
      },
      "The methods canonical_form() takes: see help(cshapes.canonical_form_methods).");
  m.def("method_options", &method_options_py,
        "Every option of the registered methods: see help(cshapes.method_options).");
  m.def("classical_mds", &classical_mds_py, py::arg("D"), py::arg("dim") = 3, py::kw_only(),
        py::arg("progress") = py::none(),
        "Classical MDS of a distance matrix: see help(cshapes.classical_mds).");
  m.def("smacof", &smacof_py, py::arg("D"), py::arg("X0") = py::none(),
        "SMACOF metric MDS of a distance matrix: see help(cshapes.smacof).");
}

}  // namespace cshapes::python
