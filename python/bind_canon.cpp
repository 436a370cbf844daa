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
#include "cshapes/pipeline/method_options.h"
#include "cshapes/pipeline/mesh_report.h"
#include "python/bindings.h"
#include "python/convert.h"
#include "python/method_argument.h"
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
  CanonicalFormOptions o;
  read_named_keywords(k, {"smacof_max_iterations", "smacof_tolerance", "accelerate", "smacof_window"}, o);
  SmacofOptions so = o.smacof;
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

// One keyword as the docstrings list it: "name ['default'] a | b" or "name [default]".
std::string keyword_doc(const MethodOption& option) {
  const std::string fallback = option_text(option_default(option));
  std::string line = option.name + " [";
  if (option.type == MethodOption::Type::Choice) {
    line += "'" + fallback + "']";
    for (size_t k = 0; k < option.choices.size(); ++k) line += (k == 0 ? " " : " | ") + option.choices[k];
  } else {
    line += fallback + "]";
  }
  return line + ": " + option.help;
}

std::string coulomb_doc() {
  std::ostringstream d;
  d << "The Coulomb canonical form of a mesh (paper §2): electrostatic repulsion under edge-length "
       "constraints.\n\n"
       "V (n, 3) coordinates, F (m, 3) vertex indices (an empty F: a point cloud, joined by its kNN graph).\n"
       "Keywords, named as `cshapes canon --method coulomb` names them (defaults in brackets):\n";
  for (const MethodOption& option : canonical_form_method("coulomb").options)
    if (option.python) d << "  " << keyword_doc(option) << "\n";
  d << "  knn [" << KnnGraphOptions{}.k
    << "]: point clouds: neighbours of the kNN graph; strict [False]: refuse a mesh that needs repair\n\n"
       "Returns a CanonicalForm: X (n, 3) in the input's vertex order and units, torn (n,) 1 at vertices of "
       "torn edges, history {energy, mean_violation, ...} per iteration, iterations, summary (dict), "
       "seconds.\n"
       "A mesh with several components or other defects is repaired for the method first (summary['repair'] "
       "says what); dropped vertices are NaN rows with valid = 0. The GIL is released while it runs.";
  return d.str();
}

// canonical_form()'s help: each method and its keywords, from the methods' own option lists (the lists the
// refusals use).
std::string canonical_form_doc() {
  std::ostringstream d;
  d << "A canonical form by any method, as `cshapes canon --method M` computes it.\n\n"
       "Each method reads its own keywords (defaults in brackets) and refuses the others, naming the methods "
       "that read them. Every method: knn [8] (point clouds: the kNN graph standing in for the edges), strict "
       "[False] (refuse a mesh that needs repair).\n";
  std::vector<std::string> described;
  for (const CanonicalFormMethod& method : canonical_form_method_registry()) {
    d << "\nmethod='" << method.name << "' (" << method.title << "): " << method.summary << "\n";
    for (const MethodOption& option : method.options) {
      if (!option.python) continue;
      if (std::find(described.begin(), described.end(), option.name) != described.end()) {
        d << "  " << option.name << " (as above)\n";
        continue;
      }
      described.push_back(option.name);
      d << "  " << keyword_doc(option) << "\n";
    }
  }
  d << "\nmethod may also be a method from outside (see docs/outside-methods.md): a function fn(V, F) -> X "
       "(an (n, 3) array, one row per vertex), a pair (name, fn), 'NAME=cmd:COMMAND' or 'NAME=forms:DIR'; "
       "keywords method_timeout [86400 s] and method_version ['']. Its form is checked as an experiment checks "
       "it (one finite row per vertex, spanning a plane) and gets the same quality verdict.\n";
  d << "\nReturns a CanonicalForm.";
  return d.str();
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
        return canonical_form_py(V, F, py::str("coulomb"), kwargs, "coulomb");
      },
      py::arg("V"), py::arg("F"), coulomb_doc().c_str());
  m.def(
      "canonical_form",
      [](const py::object& V, const py::object& F, const py::object& method, const py::kwargs& kwargs) {
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
      R"(The methods canonical_form() takes, in the library's order (pipeline/canonical_form_methods.h): a list
of dicts {name, title, summary, uses_geodesic_matrix, keywords}; name is what method= takes, title the
method's name in figures and tables ('Coulomb', 'classical MDS', 'SMACOF'), keywords the options it reads
(besides knn and strict).)");
  m.def("method_options", &method_options_py,
        R"(Every option of the registered methods, once each: a list of dicts {name, flag, type ('int', 'float',
'str'), default, choices, limit, help, methods}; name is the keyword of canonical_form(), flag the CLI's option,
methods the methods that read it. scripts/make_stub.py writes the stub's signatures from it.)");
  m.def("classical_mds", &classical_mds_py, py::arg("D"), py::arg("dim") = 3,
        R"(Classical MDS of an (n, n) distance matrix D (any real dtype; symmetric, zero diagonal).

Returns a CanonicalForm whose X is (n, dim), centred, in the units of D; dim 1..3 (the leading axes of the
3-D embedding). summary['classical_mds']: eigenvalues, most_negative_eigenvalue, explained_energy, ...
GIL released.)");
  m.def("smacof", &smacof_py, py::arg("D"), py::arg("X0") = py::none(),
        R"(SMACOF metric MDS of an (n, n) distance matrix D (stored as float32, as the library keeps them).

X0: (n, 3) start; None starts from classical MDS of D. Keywords (the CLI's): smacof_max_iterations [300],
smacof_tolerance [1e-5], accelerate ['none'] | 'rre' | 'mpe', smacof_window [6] (rre/mpe), weights [None] or
n positive vertex weights (pair weights w_i w_j). Returns a CanonicalForm: X (n, 3), history (passes, normalized_stress,
extrapolated per iteration), iterations, summary['smacof'] {normalized_stress, stop_reason, ...}. GIL released.)");
}

}  // namespace cshapes::python
