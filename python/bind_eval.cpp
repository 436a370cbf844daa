// cshapes.distance_matrix and retrieval_measures: the all-pairs distance matrix of canonical forms
// (eval/pairwise_distances.h, the computation `cshapes distmat` runs) and its retrieval measures
// (eval/retrieval_report.h, what `cshapes evaluate` writes to metrics.json).
#include <pybind11/stl.h>

#include <cmath>

#include "cshapes/eval/pairwise_distances.h"
#include "cshapes/eval/retrieval_report.h"
#include "cshapes/matching/shape_distance.h"
#include "cshapes/support/error.h"
#include "cshapes/support/threads.h"
#include "python/bindings.h"
#include "python/convert.h"
#include "python/kwargs.h"
#include "python/progress.h"
#include "python/declared_options.h"

namespace cshapes::python {

namespace {

py::array_t<double> distance_matrix_py(const py::sequence& forms, const py::kwargs& kwargs) {
  std::vector<Points> shapes;
  for (size_t i = 0; i < forms.size(); ++i) {
    py::object item = forms[i];
    if (py::hasattr(item, "X") && !py::isinstance<py::array>(item)) item = item.attr("X");
    shapes.push_back(to_points(item, "forms[" + std::to_string(i) + "]", /*allow_nonfinite=*/true));
  }
  CSHAPES_REQUIRE(shapes.size() >= 2, "distance_matrix(): forms: expected at least 2 point sets, got ",
                  shapes.size());
  Kwargs k(kwargs, "distance_matrix");
  const std::string metric = k.text("metric", "hausdorff");
  PairwiseDistanceOptions o;
  o.icp = read_icp_options(k);
  const py::object cache = k.object("cache");
  o.cache_dir = cache.is_none() ? "" : to_path(cache, "cache");
  o.threads = k.int32("threads", 0);
  const PythonProgress progress(k.object("progress"), "distance_matrix");
  o.progress = progress.fn();             // reports and Ctrl-C (python/progress.h), between pairs
  o.icp.progress = polls_of(o.progress);  // and Ctrl-C in each pair's ICP steps
  k.done();
  CSHAPES_REQUIRE(metric == "hausdorff" || metric == "chamfer" || metric == "rmse",
                  "distance_matrix(): metric: expected 'hausdorff', 'chamfer' or 'rmse', got '", metric, "'");
  CSHAPES_REQUIRE(o.threads >= 0, "distance_matrix(): threads: expected an integer >= 0, got ", o.threads);
  // Capped as the CLI caps --threads (support/threads.h): 100,000 threads crashed inside the OpenMP runtime.
  if (o.threads > 0)
    o.threads = threads_for_computation(o.threads, 1, [](const std::string& line) {
      warn("cshapes.distance_matrix: threads: " + line);
    });
  const PairwiseDistanceResult r = progress.run([&] { return pairwise_distances(shapes, {}, o); });
  return to_numpy(metric == "hausdorff" ? r.hausdorff : metric == "chamfer" ? r.chamfer : r.rmse);
}

py::object retrieval_measures_py(const py::object& D_in, const py::sequence& labels,
                                 const py::object& names_in, int min_class_size) {
  NamedDistances input;
  input.D = to_matrix(D_in, "D");
  const Index n = input.D.rows();
  CSHAPES_REQUIRE(static_cast<Index>(labels.size()) == n, "retrieval_measures(): labels: ", labels.size(),
                  " labels for a ", n, "x", n, " matrix");
  // A label is its text, and a number its value: 1 and 1.0 are one class, as 1 and "1" are.
  std::vector<std::string> classes;
  for (py::handle label : labels) {
    if (py::isinstance<py::float_>(label)) {
      const double value = label.cast<double>();
      if (std::isfinite(value) && value == std::floor(value) && std::abs(value) < 1e15) {
        classes.push_back(std::to_string(static_cast<long long>(value)));
        continue;
      }
    }
    classes.push_back(py::str(label).cast<std::string>());
  }
  if (names_in.is_none()) {
    for (Index i = 0; i < n; ++i) input.names.push_back(std::to_string(i));
  } else {
    for (py::handle name : names_in) input.names.push_back(py::str(name).cast<std::string>());
    CSHAPES_REQUIRE(static_cast<Index>(input.names.size()) == n,
                    "retrieval_measures(): names: ", input.names.size(), " names for a ", n, "x", n,
                    " matrix");
  }
  for (Index i = 0; i < n; ++i)
    for (Index j = 0; j < n; ++j)
      CSHAPES_REQUIRE(std::isfinite(input.D(i, j)), "retrieval_measures(): D[", i, ", ", j, "] is ",
                      input.D(i, j), ", expected a finite distance");
  // The rules `cshapes evaluate` applies (eval/distance_csv.h): negative distances and two shapes of one name
  // refused, an asymmetric matrix and a non-zero diagonal warned; min_class_size as --min-class-size.
  for (const std::string& line : check_distance_matrix(input, "retrieval_measures(): D"))
    warn("cshapes.retrieval_measures: " + line);
  CSHAPES_REQUIRE(min_class_size >= 1, "retrieval_measures(): min_class_size: expected an integer >= 1, got ",
                  min_class_size);
  RetrievalOptions options;
  options.min_class_size = min_class_size;
  RetrievalReport report;
  {
    Computing computing;
    report = retrieval_report(input, classes, options, "numpy array");
  }
  nlohmann::json j = report.metrics;
  j["confusion"] = confusion_json(report.result.confusion);
  j["class_names"] = report.class_names;
  return to_python(j);
}

}  // namespace

void bind_eval(py::module_& m) {
  declare_keywords("distance_matrix", icp_options::kAll);
  declare_keywords("distance_matrix", {&kMetricOption});
  declare_keywords("retrieval_measures", {&kEvaluateMinClassSizeOption});
  // One-line docstrings: cshapes/_api.py documents the Python functions (signature, numpy sections).
  m.def("distance_matrix", &distance_matrix_py, py::arg("forms"),
        "The all-pairs distance matrix of canonical forms: see help(cshapes.distance_matrix).");
  m.def("retrieval_measures", &retrieval_measures_py, py::arg("D"), py::arg("labels"), py::kw_only(),
        py::arg("names") = py::none(), py::arg("min_class_size") = 3,
        "Retrieval measures of a distance matrix: see help(cshapes.retrieval_measures).");
}

}  // namespace cshapes::python
