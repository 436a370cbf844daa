// cshapes.experiment_paper and cshapes.experiment_retrieval: the experiments (experiments/paper_experiment.h,
// experiments/retrieval_experiment.h) from Python, with the library's defaults, so a run from Python, from C++ and
// `cshapes experiment paper|retrieval` with the same options writes the same files. cshapes.show: the picture of
// `cshapes show` (experiments/show_mesh.h). cshapes.compare_runs: `cshapes compare`
// (experiments/compare_runs.h). cshapes.experiment_noise, _pose, _topkids and _invariance: the experiments on a
// dataset's shapes (experiments/noise_experiment.h, pose_invariance.h, topkids_experiment.h,
// invariance_experiment.h), with the same keywords.
#include <pybind11/stl.h>

#include <filesystem>
#include <fstream>
#include <optional>

#include "cshapes/experiments/compare_runs.h"
#include "cshapes/experiments/invariance_experiment.h"
#include "cshapes/experiments/noise_experiment.h"
#include "cshapes/experiments/paper_experiment.h"
#include "cshapes/experiments/pose_invariance.h"
#include "cshapes/experiments/retrieval_experiment.h"
#include "cshapes/pipeline/dataset_distances.h"
#include "cshapes/experiments/show_mesh.h"
#include "cshapes/experiments/topkids_experiment.h"
#include "cshapes/pipeline/canonical_form_methods.h"
#include "cshapes/pipeline/outside_methods.h"
#include "cshapes/pipeline/shape_failures.h"
#include "cshapes/support/output_folder.h"
#include "cshapes/support/sha256.h"
#include "python/bindings.h"
#include "python/convert.h"
#include "python/interrupt.h"
#include "python/method_argument.h"
#include "python/progress.h"
#include "python/declared_options.h"

namespace cshapes::python {

namespace py = pybind11;

namespace {

py::dict experiment_paper_py(const py::object& data, const py::object& out, const py::object& methods,
                             int poses_per_class, int noisy_per_class, bool table1, bool figures, bool draw,
                             const py::kwargs& kwargs) {
  PaperExperimentOptions o;
  o.data = to_path(data, "data");
  o.out = to_path(out, "out");

  CSHAPES_REQUIRE(poses_per_class >= 0, "experiment_paper(): poses_per_class: expected 0 (all) or more, got ",
                  poses_per_class);
  CSHAPES_REQUIRE(noisy_per_class >= -1,
                  "experiment_paper(): noisy_per_class: expected -1 (every pose), 0 or more, got ",
                  noisy_per_class);
  o.poses_per_class = poses_per_class;
  o.noisy_per_class = noisy_per_class;
  o.table1 = table1;
  o.figures = figures;
  o.draw = draw;
  Kwargs k(kwargs, "experiment_paper");
  const MethodArgument method_list = method_argument(methods, "experiment_paper", k);
  if (!methods.is_none()) o.methods = method_list.names;
  o.glue = k.int32("glue", o.glue);
  o.seed = static_cast<std::uint64_t>(k.integer("seed", static_cast<long long>(o.seed), 0));
  o.timing_repeats = k.int32("table1_repeats", o.timing_repeats);
  o.force = k.flag("force", o.force);
  o.allow_outside = k.flag("allow_outside", o.allow_outside);
  o.correspondence_samples = k.int32("correspondence_samples", o.correspondence_samples);
  o.figure_format = parse_figure_format(k.text("figure_format", to_string(o.figure_format)));
  o.canon.strict = k.flag("strict", o.canon.strict);
  o.canon.geodesics.method =
      parse_geodesic_method(k.text("geodesics", to_string(o.canon.geodesics.method)));
  o.resample.vertices = static_cast<Index>(k.integer("resample", 0, 0));
  CSHAPES_REQUIRE(o.resample.vertices == 0 || o.resample.vertices >= 4,
                  "experiment_paper(): resample: expected 0 (off) or at least 4 vertices, got ",
                  o.resample.vertices);
  const PythonProgress progress(k.object("progress"), "experiment_paper");
  k.done();
  o.progress = progress.fn();  // reports and Ctrl-C (python/progress.h)
  const PaperExperimentSummary s = progress.run([&] { return paper_experiment(o); });
  py::dict result;
  result["out"] = o.out;
  result["shapes"] = s.shapes;
  result["seconds"] = s.seconds;
  result["canonical_forms_computed"] = s.canonical_forms_computed;
  result["canonical_forms_cached"] = s.canonical_forms_cached;
  result["pairs_computed"] = s.pairs_computed;
  result["pairs_cached"] = s.pairs_cached;
  result["figures_drawn"] = s.figures_drawn;
  result["failures"] = python::to_python(shape_failures_json(s.failures));
  return result;
}

py::dict experiment_retrieval_py(const py::object& data, const py::object& out, const py::object& methods,
                                 long long resample, bool draw, const py::kwargs& kwargs) {
  RetrievalExperimentOptions o;
  o.data = to_path(data, "data");
  o.out = to_path(out, "out");

  CSHAPES_REQUIRE(resample == 0 || (resample >= 4 && resample <= 100000000),
                  "experiment_retrieval(): resample: expected 0 (off) or a vertex count from 4 to 100000000, got ",
                  resample);
  o.resample.vertices = static_cast<Index>(resample);
  o.figures = draw;
  Kwargs k(kwargs, "experiment_retrieval");
  const MethodArgument method_list = method_argument(methods, "experiment_retrieval", k);
  if (!methods.is_none()) o.methods = method_list.names;
  o.canon.strict = k.flag("strict", o.canon.strict);
  o.canon.geodesics.method =
      parse_geodesic_method(k.text("geodesics", to_string(o.canon.geodesics.method)));
  o.retrieval.e_measure_depth = k.int32("e_depth", o.retrieval.e_measure_depth);
  o.retrieval.min_class_size = k.int32("min_class_size", o.retrieval.min_class_size);
  o.two_stage_k = k.int32("two_stage_k", o.two_stage_k);
  CSHAPES_REQUIRE(o.two_stage_k >= 0, "experiment_retrieval(): two_stage_k: expected an integer >= 0, got ",
                  o.two_stage_k);
  if (const py::object reference = k.object("two_stage_reference"); !reference.is_none())
    o.two_stage_reference = to_path(reference, "two_stage_reference");
  o.figure_format = parse_figure_format(k.text("figure_format", to_string(o.figure_format)));
  o.force = k.flag("force", o.force);
  o.allow_outside = k.flag("allow_outside", o.allow_outside);
  const PythonProgress progress(k.object("progress"), "experiment_retrieval");
  k.done();
  o.progress = progress.fn();  // reports and Ctrl-C (python/progress.h)
  const RetrievalExperimentResult r = progress.run([&] { return retrieval_experiment(o); });
  py::dict measures, two_stage;
  for (const RetrievalMethodResult& m : r.methods) {
    py::dict per;
    for (const auto& [kind, report] : m.by_distance)
      per[py::str(kind)] = python::to_python(retrieval_scores_json(report.result.mean));
    measures[py::str(m.method)] = per;
    if (o.two_stage_k > 0) {
      nlohmann::json two{{"k", o.two_stage_k}, {"pairs_aligned", m.pairs_aligned}};
      if (m.recall >= 0) two["recall_at_k"] = m.recall;
      for (const auto& [kind, scores] : m.exact) two["exact"][kind] = retrieval_scores_json(scores);
      two_stage[py::str(m.method)] = python::to_python(two);
    }
  }
  py::dict result;
  result["out"] = o.out;
  result["shapes"] = r.shapes;
  result["classes"] = r.class_names;
  if (o.two_stage_k > 0) result["two_stage"] = two_stage;
  result["seconds"] = r.seconds;
  result["resampled"] = r.resampled;
  result["measures"] = measures;
  result["figures"] = r.figures;
  result["failures"] = python::to_python(shape_failures_json(r.failures));
  return result;
}

py::dict compare_runs_py(const py::object& runs, const py::object& out, bool draw,
                         const std::string& figure_format, bool force) {
  CompareRunsOptions o;
  CSHAPES_REQUIRE(!py::isinstance<py::str>(runs) && py::isinstance<py::sequence>(runs),
                  "compare_runs(): runs: expected a list of output folders, got ",
                  std::string(py::str(py::type::of(runs).attr("__name__"))));
  for (const py::handle& run : runs) o.runs.push_back(to_path(run, "runs"));
  o.out = to_path(out, "out");
  o.figures = draw;
  o.figure_format = parse_figure_format(figure_format);
  o.force = force;
  const CompareRunsResult r = compare_runs(o);
  py::dict measures, from;
  for (const ComparedMethod& m : r.methods) {
    py::dict per;
    for (const auto& [kind, scores] : m.scores)
      per[py::str(kind)] = python::to_python(retrieval_scores_json(scores));
    measures[py::str(m.method)] = per;
    from[py::str(m.method)] = r.runs[m.run].folder;
  }
  py::dict result;
  result["out"] = o.out;
  result["experiment"] = r.experiment;
  result["inputs_digest"] = r.inputs_digest;
  result["shapes"] = r.shapes;
  result["measures"] = measures;
  result["runs"] = from;
  result["figures"] = r.figures;
  return result;
}

bool is_path(const py::handle& object) {
  return py::isinstance<py::str>(object) || py::hasattr(object, "__fspath__");
}

// One panel of show(): a mesh file (any format the library reads), a CanonicalForm (titled by its method), a
// (V, F) pair, or an (n, 3) array (a form: drawn with the mesh's faces; a mesh: a point cloud). NaN rows pass
// (vertices a method dropped). name: the argument, in messages.
ShowPanel show_panel(const py::handle& object, const std::string& name, bool form) {
  if (is_path(object)) {
    const std::string path = to_path(object, name);
    py::gil_scoped_release release;
    return read_show_panel(path, form);
  }
  if (py::hasattr(object, "X") && !py::isinstance<py::array>(object)) {
    std::string method;
    if (py::hasattr(object, "summary")) {
      const py::object summary = object.attr("summary");
      if (py::isinstance<py::dict>(summary) && summary.contains("method"))
        method = py::str(summary["method"]).cast<std::string>();
    }
    return ShowPanel{Mesh{to_points(object.attr("X"), name + ".X", true), Faces(0, 3)},
                     form_panel_title(method), ""};
  }
  const std::string title = form ? form_panel_title("") : "mesh";
  if (py::isinstance<py::tuple>(object) || py::isinstance<py::list>(object)) {
    const py::sequence items = py::reinterpret_borrow<py::sequence>(object);
    if (items.size() == 2 && !py::isinstance<py::float_>(items[0]) && !py::isinstance<py::int_>(items[0]))
      return ShowPanel{Mesh{to_points(items[0], name + " V", true), to_faces(items[1], name + " F")}, title,
                       ""};
  }
  return ShowPanel{Mesh{to_points(object, name, true), Faces(0, 3)}, title, ""};
}

std::string show_py(const py::object& mesh, const py::object& form, const py::object& out,
                    const py::object& title, const std::string& view, const py::object& labels,
                    const py::object& figure_format) {
  std::optional<FigureFormat> format;
  if (!figure_format.is_none()) format = parse_figure_format(py::str(figure_format).cast<std::string>());
  const std::string picture = picture_path(to_path(out, "out"), format);
  ShowOptions options;
  if (!title.is_none()) options.title = py::str(title).cast<std::string>();
  options.view = view;
  ShowPanel mesh_panel = show_panel(mesh, "mesh", false);
  std::optional<ShowPanel> form_panel;
  if (!form.is_none()) form_panel = show_panel(form, "form", true);
  if (!labels.is_none()) {
    CSHAPES_REQUIRE(!py::isinstance<py::str>(labels) && py::isinstance<py::sequence>(labels),
                    "show(): labels: expected a list of panel titles (the mesh's, then the form's), got ",
                    py::repr(labels).cast<std::string>());
    const auto titles = labels.cast<std::vector<std::string>>();
    CSHAPES_REQUIRE(titles.size() <= (form_panel ? 2u : 1u), "show(): labels: ", titles.size(),
                    " titles for ", form_panel ? "2 panels" : "1 panel", " (the mesh's, then the form's)");
    if (!titles.empty()) mesh_panel.title = titles[0];
    if (titles.size() > 1) form_panel->title = titles[1];
  }
  py::gil_scoped_release release;
  show_panels(mesh_panel, form_panel ? &*form_panel : nullptr, picture, options);
  return picture;
}

}  // namespace

namespace {

// The experiments' common keywords and the methods argument, for noise, pose and topkids.
template <class Options>
void common_experiment_options(Options& o, const py::object& data, const py::object& out, Kwargs& k) {
  o.data = to_path(data, "data");
  o.out = to_path(out, "out");
  o.force = k.flag("force", o.force);
  o.allow_outside = k.flag("allow_outside", o.allow_outside);
  o.canon.strict = k.flag("strict", o.canon.strict);
  o.canon.geodesics.method = parse_geodesic_method(k.text("geodesics", to_string(o.canon.geodesics.method)));
  o.resample.vertices = static_cast<Index>(k.integer("resample", 0, 0));
  o.figure_format = parse_figure_format(k.text("figure_format", to_string(o.figure_format)));
}

// The run's results as the CLI writes them (OUT/NAME, a JSON file), with the failures.
py::dict experiment_result(const std::string& out, const std::string& json_name,
                           const std::vector<ShapeFailure>& failures) {
  py::dict result;
  result["out"] = out;
  const std::string path = (std::filesystem::path(out) / json_name).string();
  if (std::filesystem::exists(path)) {
    std::ifstream in(path);
    result["results"] = python::to_python(nlohmann::json::parse(in));
  }
  result["failures"] = python::to_python(shape_failures_json(failures));
  return result;
}

}  // namespace

py::dict experiment_noise_py(const py::object& data, const py::object& out, const py::object& methods, bool draw,
                             const py::kwargs& kwargs) {
  NoiseExperimentOptions o;
  Kwargs k(kwargs, "experiment_noise");
  const MethodArgument method_list = method_argument(methods, "experiment_noise", k);
  if (!methods.is_none()) o.methods = method_list.names;
  common_experiment_options(o, data, out, k);
  o.seed = static_cast<std::uint64_t>(k.integer("seed", static_cast<long long>(o.seed), 0));
  o.poses_per_class = k.int32("poses_per_class", o.poses_per_class);
  if (k.given("levels")) o.levels = k.object("levels").cast<std::vector<int>>();
  const PythonProgress progress(k.object("progress"), "experiment_noise");
  k.done();
  o.figure = draw;
  o.progress = progress.fn();  // reports and Ctrl-C (python/progress.h)
  const NoiseExperimentResult r = progress.run([&] { return noise_experiment(o); });
  return experiment_result(o.out, "noise.json", r.failures);
}

py::dict experiment_pose_py(const py::object& data, const py::object& out, const py::object& methods, bool draw,
                            const py::kwargs& kwargs) {
  PoseInvarianceOptions o;
  Kwargs k(kwargs, "experiment_pose");
  const MethodArgument method_list = method_argument(methods, "experiment_pose", k);
  if (!methods.is_none()) o.methods = method_list.names;
  common_experiment_options(o, data, out, k);
  o.samples = k.int32("samples", o.samples);
  o.parts = k.flag("parts", o.parts);
  if (k.given("shapes")) o.shapes = k.object("shapes").cast<std::vector<std::string>>();
  const PythonProgress progress(k.object("progress"), "experiment_pose");
  k.done();
  o.figure = draw;
  o.canon.progress = progress.fn();  // reports and Ctrl-C (python/progress.h)
  const PoseInvarianceResult r = progress.run([&] { return pose_experiment(o); });
  return experiment_result(o.out, "pose_residuals.json", r.failures);
}

py::dict experiment_topkids_py(const py::object& data, const py::object& out, const py::object& methods, bool draw,
                               const py::kwargs& kwargs) {
  TopkidsExperimentOptions o;
  Kwargs k(kwargs, "experiment_topkids");
  const MethodArgument method_list = method_argument(methods, "experiment_topkids", k);
  if (!methods.is_none()) o.methods = method_list.names;
  common_experiment_options(o, data, out, k);
  o.reference = k.text("reference", o.reference);
  o.samples = k.int32("samples", o.samples);
  if (k.given("poses")) o.poses = k.object("poses").cast<std::vector<std::string>>();
  const PythonProgress progress(k.object("progress"), "experiment_topkids");
  k.done();
  o.figure = draw;
  o.progress = progress.fn();  // reports and Ctrl-C (python/progress.h)
  const TopkidsExperimentResult r = progress.run([&] { return topkids_experiment(o); });
  return experiment_result(o.out, "topkids.json", r.failures);
}

py::dict experiment_invariance_py(const py::object& data, const py::object& out, const py::object& methods,
                                  bool draw, const py::kwargs& kwargs) {
  InvarianceOptions o;
  Kwargs k(kwargs, "experiment_invariance");
  const MethodArgument method_list = method_argument(methods, "experiment_invariance", k);
  if (!methods.is_none()) o.methods = method_list.names;
  o.data = to_path(data, "data");
  o.out = to_path(out, "out");
  o.force = k.flag("force", o.force);
  o.allow_outside = k.flag("allow_outside", o.allow_outside);
  o.canon.strict = k.flag("strict", o.canon.strict);
  o.canon.geodesics.method = parse_geodesic_method(k.text("geodesics", to_string(o.canon.geodesics.method)));
  if (const py::object v = k.object("vertices"); !v.is_none()) {
    try {
      o.vertices =
          py::isinstance<py::int_>(v) ? std::vector<Index>{v.cast<Index>()} : v.cast<std::vector<Index>>();
    } catch (const py::cast_error&) {
      fail("experiment_invariance(): vertices: expected a vertex count or a list of them (0: the shapes as ",
           "given), got ", py::repr(v).cast<std::string>());
    }
  }
  o.seeds = k.int32(invariance_options::kSeeds, o.seeds);
  o.seed = static_cast<std::uint64_t>(k.integer("seed", static_cast<long long>(o.seed), 0,
                                                static_cast<long long>(invariance_limits::kSeed.maximum)));
  o.tolerance_floor_percent = k.number(invariance_options::kToleranceFloor, o.tolerance_floor_percent);
  o.tolerance_pose_percent = k.number(invariance_options::kTolerancePose, o.tolerance_pose_percent);
  if (const py::object shapes = k.object("shapes"); !shapes.is_none())
    o.shapes = shapes.cast<std::vector<std::string>>();
  o.figure_format = parse_figure_format(k.text("figure_format", to_string(o.figure_format)));
  const PythonProgress progress(k.object("progress"), "experiment_invariance");
  k.done();
  o.figure = draw;
  o.progress = progress.fn();  // reports and Ctrl-C (python/progress.h)
  const InvarianceResult r = progress.run([&] { return invariance_experiment(o); });
  return experiment_result(o.out, "invariance.json", r.failures);
}

namespace {

// experiment_noise, experiment_pose, experiment_topkids and experiment_invariance.
void bind_dataset_experiments(py::module_& m) {
  m.def("experiment_noise", &experiment_noise_py, py::arg("data"), py::arg("out"),
        py::arg("methods") = py::none(), py::arg("draw") = true,
        "Retrieval under topological noise: see help(cshapes.experiment_noise).");
  m.def("experiment_pose", &experiment_pose_py, py::arg("data"), py::arg("out"),
        py::arg("methods") = py::none(), py::arg("draw") = true,
        "Pose residuals, per part: see help(cshapes.experiment_pose).");
  m.def("experiment_topkids", &experiment_topkids_py, py::arg("data"), py::arg("out"),
        py::arg("methods") = py::none(), py::arg("draw") = true,
        "SHREC'16 TOPKIDS correspondence curves: see help(cshapes.experiment_topkids).");
  m.def("experiment_invariance", &experiment_invariance_py, py::arg("data"), py::arg("out"),
        py::arg("methods") = py::none(), py::arg("draw") = true,
        "How much each canonical form changes under what must not change it: see "
        "help(cshapes.experiment_invariance).");
}

}  // namespace

namespace {
// The keywords each function shares with its command's flags, documented by their declarations.
void declare_experiment_keywords() {
  const std::vector<const OptionDeclaration*> outside = outside_method_options::kAll;
  std::vector<const OptionDeclaration*> common = {&kResampleOption, &kFigureFormatOption, &kForceOption,
                                                  &kAllowOutsideOption};
  common.insert(common.end(), outside.begin(), outside.end());
  for (const char* f : {"experiment_paper", "experiment_retrieval", "experiment_noise", "experiment_topkids"})
    declare_keywords(f, common);
  declare_keywords("experiment_pose", common);
  declare_keywords("experiment_pose", {&kShapesOption});
  declare_keywords("experiment_invariance",
                   {&kFigureFormatOption, &kForceOption, &kAllowOutsideOption, &kShapesOption});
  declare_keywords("experiment_invariance", outside);
  declare_keywords("experiment_invariance", invariance_options::kAll);
  declare_keywords("compare_runs",
                   {&kCompareOutOption, &kCompareDrawOption, &kFigureFormatOption, &kForceOption});
  declare_keywords("show", {&show_options::kTitle, &show_options::kView, &kFigureFormatOption});
  declare_keywords("canonical_form", outside);
  declare_keywords("canonical_form", {&kStrictFormOption});
  declare_keywords("coulomb", {&kStrictFormOption});
  declare_keywords("experiment_paper", paper_experiment_options::kAll);
  declare_keywords("experiment_retrieval", retrieval_experiment_options::kAll);
  declare_keywords("experiment_retrieval", {&kTwoStageKOption});
  declare_keywords("experiment_noise", noise_experiment_options::kAll);
  declare_keywords("experiment_pose", {&pose_experiment_options::kSamples, &pose_experiment_options::kDraw,
                                       &pose_experiment_options::kParts});
  declare_keywords("experiment_topkids", topkids_options::kAll);
  for (const char* f : {"experiment_paper", "experiment_retrieval", "experiment_noise", "experiment_pose",
                        "experiment_topkids", "experiment_invariance"})
    declare_keywords(f, {&kStrictRunOption, &kOutFolderOption});
  declare_keywords("experiment_paper", {&paper_experiment_options::kData});
  declare_keywords("experiment_retrieval", {&retrieval_experiment_options::kData});
  declare_keywords("experiment_noise", {&noise_experiment_options::kData});
  declare_keywords("experiment_pose", {&pose_experiment_options::kData});
  declare_keywords("experiment_topkids", {&topkids_options::kData});
  declare_keywords("experiment_invariance", {&invariance_options::kData});
}
}  // namespace

void bind_experiments(py::module_& m) {
  declare_experiment_keywords();
  // One-line docstrings: cshapes/_api.py documents the Python functions (signature, numpy sections).
  m.def("show", &show_py, py::arg("mesh"), py::arg("form") = py::none(), py::kw_only(), py::arg("out"),
        py::arg("title") = py::none(), py::arg("view") = "pca", py::arg("labels") = py::none(),
        py::arg("figure_format") = py::none(), "A picture of a mesh and its form: see help(cshapes.show).");
  m.def("experiment_paper", &experiment_paper_py, py::arg("data"), py::arg("out"),
        py::arg("methods") = py::none(), py::arg("poses_per_class") = 4, py::arg("noisy_per_class") = 1,
        py::arg("table1") = true, py::arg("figure_data") = true, py::arg("draw") = true,
        "The paper's experiment end to end: see help(cshapes.experiment_paper).");
  bind_dataset_experiments(m);
  m.def("experiment_retrieval", &experiment_retrieval_py, py::arg("data"), py::arg("out"),
        py::arg("methods") = py::none(), py::arg("resample") = 0, py::arg("draw") = true,
        "A collection as a retrieval benchmark: see help(cshapes.experiment_retrieval).");
  m.def("compare_runs", &compare_runs_py, py::arg("runs"), py::arg("out"), py::kw_only(),
        py::arg("draw") = true, py::arg("figure_format") = "png", py::arg("force") = false,
        "Several retrieval runs side by side: see help(cshapes.compare_runs).");
}

}  // namespace cshapes::python
