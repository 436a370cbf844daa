#include "cshapes/experiments/retrieval_experiment.h"

#include <algorithm>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <set>

#include <omp.h>

#include "cshapes/data/classification.h"
#include "cshapes/support/atomic_file.h"
#include "cshapes/data/dataset.h"
#include "cshapes/support/error.h"
#include "cshapes/support/timing.h"
#include "cshapes/support/output_folder.h"
#include "cshapes/eval/distance_csv.h"
#include "cshapes/experiments/figures.h"
#include "cshapes/experiments/outside_methods_report.h"
#include "cshapes/pipeline/dataset_distances.h"
#include "cshapes/pipeline/experiment_kit.h"

namespace cshapes {

namespace fs = std::filesystem;
using nlohmann::json;

const std::vector<std::string>& retrieval_distances() {
  static const std::vector<std::string> names = {"hausdorff", "chamfer", "rmse"};
  return names;
}

namespace {

const Eigen::MatrixXd& distance_matrix(const PairwiseDistanceResult& d, const std::string& name) {
  return name == "hausdorff" ? d.hausdorff : name == "chamfer" ? d.chamfer : d.rmse;
}

// One method's matrices in every form and their measures, under each distance (rank 0).
void write_method_files(const ExperimentFolder& folder, const RetrievalExperimentOptions& o,
                        const DatasetDistances& dd, RetrievalMethodResult& m) {
  write_classification(folder.path(m.method + "/classes.cla"),
                       classification_from_labels(m.names, m.classes));
  for (const std::string& kind : retrieval_distances()) {
    const NamedDistances named{m.names, distance_matrix(dd.distances, kind)};
    const std::string base = m.method + "/" + kind;
    write_distance_csv(folder.path(base + ".csv"), named.names, named.D);
    write_dissimilarity_text(folder.path(base + ".txt"), named.D);
    write_psb_matrix(folder.path(base + ".matrix"), named.D);
    RetrievalReport report = retrieval_report(named, m.classes, o.retrieval, folder.path(base + ".csv"));
    write_retrieval_report(folder.path(base), named, report);
    m.by_distance.emplace(kind, std::move(report));
  }
}

// What, besides the inputs, makes two runs' measures comparable: the measures' conventions and the
// resampling.
json retrieval_protocol_json(const RetrievalExperimentOptions& o) {
  json j{{"e_measure_depth", o.retrieval.e_measure_depth},
         {"min_class_size", o.retrieval.min_class_size},
         {"resample_vertices", o.resample.vertices}};
  // Only in two-stage runs: exact runs keep the protocol of the runs before the mode existed.
  if (o.two_stage_k > 0) j["two_stage_k"] = o.two_stage_k;
  return j;
}

// retrieval.json: every measure of the run (the figures' input).
json result_json(const RetrievalExperimentResult& r) {
  json methods = json::array();
  for (const RetrievalMethodResult& m : r.methods) {
    json distances = json::object();
    for (const auto& [kind, report] : m.by_distance) {
      json entry = report.metrics;
      entry["class_names"] = report.class_names;
      entry["confusion"] = confusion_json(report.result.confusion);
      distances[kind] = entry;
    }
    methods.push_back({{"method", m.method},
                       {"title", canonical_form_method_title(m.method)},
                       {"shapes", m.names.size()},
                       {"forms_computed", m.forms_computed},
                       {"forms_cached", m.forms_cached},
                       {"pairs_computed", m.pairs_computed},
                       {"pairs_cached", m.pairs_cached},
                       {"seconds", m.seconds},
                       {"form_seconds_median", m.form_seconds_median},
                       {"form_peak_memory_bytes", m.form_peak_bytes_max < 0 ? nlohmann::json(nullptr)
                                                                             : nlohmann::json(m.form_peak_bytes_max)},
                       {"distances", distances}});
    if (r.options.two_stage_k > 0) {
      json& two = methods.back()["two_stage"];
      two = {{"k", r.options.two_stage_k}, {"pairs_aligned", m.pairs_aligned}};
      if (m.recall >= 0) two["recall_at_k"] = m.recall;
      if (!m.exact.empty()) {
        two["reference"] = r.options.two_stage_reference;
        for (const auto& [kind, scores] : m.exact) two["exact"][kind] = retrieval_scores_json(scores);
      }
    }
  }
  json shapes_read = json::array();
  for (const ShapeChecksum& s : r.inputs.shapes)
    shapes_read.push_back({{"name", s.name}, {"class", s.class_name}, {"sha256", s.sha256}});
  json j{{"experiment", "retrieval"},
         {"data", r.options.data},
         {"read", r.data},
         {"inputs", {{"digest", r.inputs.digest}, {"shapes", shapes_read}}},
         {"protocol", retrieval_protocol_json(r.options)},
         {"shapes", r.shapes},
         {"classes", r.class_names},
         {"class_sizes", r.class_sizes},
         {"distances", retrieval_distances()},
         {"methods", methods},
         {"failures", shape_failures_json(r.failures)},
         {"seconds", r.seconds},
         {"cores", r.cores},
         {"profile", stage_times_json(r.profile)}};
  if (r.resampled) {
    json shapes = json::array();
    for (const ResampledShape& s : r.resampling.shapes)
      shapes.push_back({{"shape", s.name},
                        {"input_vertices", s.input_vertices},
                        {"vertices", s.vertices},
                        {"remeshed", s.remeshed},
                        {"hausdorff_over_diagonal", s.remeshed ? json(s.hausdorff) : json(nullptr)},
                        {"min_angle_deg", s.remeshed ? json(s.min_angle) : json(nullptr)},
                        {"note", s.note}});
    j["resample"] = {{"vertices", r.resampling.options.vertices}, {"shapes", shapes}};
  }
  return j;
}

// Two-stage options checked before any work: a reference without K, a reference that is not an exact run's
// folder of every method asked for, or one that this run would write into.
void check_two_stage(const RetrievalExperimentOptions& o) {
  CSHAPES_REQUIRE(o.two_stage_k >= 0, "experiment retrieval: two-stage K = ", o.two_stage_k, ", expected >= 0");
  if (o.two_stage_reference.empty()) return;
  CSHAPES_REQUIRE(o.two_stage_k > 0, "experiment retrieval: --two-stage-reference ", o.two_stage_reference,
                  ": applies to the two-stage mode only (--two-stage-k K > 0)");
  const fs::path ref = fs::weakly_canonical(o.two_stage_reference), out = fs::weakly_canonical(o.out);
  CSHAPES_REQUIRE(ref != out, "experiment retrieval: --two-stage-reference ", o.two_stage_reference,
                  " is the output folder: a run replaces its folder's outputs, so the exact run would be lost; "
                  "give the two-stage run another --out");
  for (const std::string& method : o.methods)
    for (const std::string& kind : retrieval_distances()) {
      const fs::path file = ref / method / (kind + ".csv");
      CSHAPES_REQUIRE(fs::is_regular_file(file), "experiment retrieval: --two-stage-reference ",
                      o.two_stage_reference, ": no ", (fs::path(method) / (kind + ".csv")).string(),
                      " (expected the output folder of an exact `cshapes experiment retrieval` run of the "
                      "same collection with method ", method, ")");
      CSHAPES_REQUIRE(fs::is_regular_file(ref / method / "classes.cla"), "experiment retrieval: ",
                      "--two-stage-reference ", o.two_stage_reference, ": no ", method, "/classes.cla");
    }
  const std::string protocol = (ref / "retrieval.json").string();
  if (fs::is_regular_file(protocol)) {
    const json j = json::parse(read_text_file(protocol));
    CSHAPES_REQUIRE(!j.contains("protocol") || !j["protocol"].contains("two_stage_k"),
                    "experiment retrieval: --two-stage-reference ", o.two_stage_reference,
                    ": a two-stage run (two_stage_k = ", j["protocol"].value("two_stage_k", json()).dump(),
                    "), expected an exact one");
  }
}

// The exact run's measures of `method` under each distance, from its matrices and classes, with this run's
// conventions.
std::map<std::string, RetrievalScores> exact_measures(const RetrievalExperimentOptions& o,
                                                      const std::string& method) {
  const fs::path ref = fs::path(o.two_stage_reference) / method;
  std::map<std::string, std::string> class_of;
  for (const ClassificationClass& c : read_classification((ref / "classes.cla").string()).classes)
    for (const std::string& model : c.models) class_of[model] = c.name;
  std::map<std::string, RetrievalScores> exact;
  for (const std::string& kind : retrieval_distances()) {
    const NamedDistances named = read_distance_csv((ref / (kind + ".csv")).string());
    std::vector<std::string> classes;
    for (const std::string& name : named.names) {
      const auto it = class_of.find(name);
      CSHAPES_REQUIRE(it != class_of.end(), (ref / (kind + ".csv")).string(), ": shape '", name,
                      "' is in no class of ", (ref / "classes.cla").string());
      classes.push_back(it->second);
    }
    exact.emplace(kind, retrieval_report(named, classes, o.retrieval, (ref / (kind + ".csv")).string()).result.mean);
  }
  return exact;
}

// What dataset_distances computes for `method` in this run ("" for the forms pass ahead of the methods').
DatasetDistanceOptions distance_options(const RetrievalExperimentOptions& o, const RetrievalExperimentResult& r,
                                        const ExperimentFolder& folder, const Communicator& comm,
                                        const std::string& method) {
  DatasetDistanceOptions dd;
  dd.data = r.data;
  dd.allow_outside = o.allow_outside || r.resampled;
  dd.canon = o.canon;
  if (!method.empty()) dd.canon.method = method;
  dd.cache_dir = folder.path("cache");
  dd.progress = o.progress;
  if (!method.empty()) dd.note = o.note;
  dd.communicator = &comm;
  dd.two_stage_k = o.two_stage_k;
  if (!o.two_stage_reference.empty() && !method.empty())
    dd.reference = (fs::path(o.two_stage_reference) / method / "hausdorff.csv").string();
  return dd;
}

// A method's result without its measures: shapes, counts (`computed_ahead` forms computed by the pass ahead
// of its own, which read them from the cache), form times, and two-stage's pairs and recall.
RetrievalMethodResult method_counts(const std::string& method, const DatasetDistances& distances,
                                    long computed_ahead) {
  RetrievalMethodResult m;
  m.method = method;
  m.names = distances.names;
  m.classes = distances.classes;
  m.forms_computed = distances.forms_computed + computed_ahead;
  m.forms_cached = distances.forms_cached - computed_ahead;
  m.pairs_computed = distances.distances.computed;
  m.pairs_cached = distances.distances.cached;
  if (!distances.form_seconds.empty()) {
    std::vector<double> t = distances.form_seconds;
    std::nth_element(t.begin(), t.begin() + static_cast<long>(t.size() / 2), t.end());
    m.form_seconds_median = t[t.size() / 2];
    for (double b : distances.form_peak_bytes) m.form_peak_bytes_max = std::max(m.form_peak_bytes_max, b);
  }
  m.pairs_aligned = distances.distances.pairs;
  m.recall = distances.two_stage.recall;
  return m;
}

}  // namespace

RetrievalExperimentResult run_retrieval_experiment(const RetrievalExperimentOptions& o) {
  const auto start = WallClock::now();
  const Communicator& comm = o.communicator ? *o.communicator : single_process();
  CSHAPES_REQUIRE(!o.methods.empty(), "experiment retrieval: no method given");
  require_canonical_form_methods(o.methods, "experiment retrieval");
  check_two_stage(o);
  const ExperimentFolder folder(o.out);
  RetrievalExperimentResult r;
  r.options = o;
  r.options.progress = {};
  r.options.note = {};
  r.options.communicator = nullptr;
  r.data = o.data;
  r.cores = std::max(1, omp_get_num_procs());
  if (o.resample.vertices > 0) {
    const Stopwatch watch;
    r.resampling = resample_dataset(o.data, o.resample, folder.path("resampled"), folder.cache("remeshed"),
                                    &comm, o.note, o.allow_outside);
    r.profile.push_back(stage_time("resample", "", watch));
    r.resampled = true;
    r.data = r.resampling.data;
    for (const ShapeFailure& record : resample_records(r.resampling)) r.failures.push_back(record);
  }
  // The remeshed collection's manifest lists kept shapes by their own paths.
  const Dataset data = read_dataset(r.data, o.allow_outside || r.resampled);
  r.shapes = static_cast<int>(data.entries.size());
  r.class_names = data.classes;
  r.class_sizes.assign(data.classes.size(), 0);
  for (int label : data.labels()) ++r.class_sizes[static_cast<size_t>(label)];
  // Before any work: a collection without a class large enough gives no query at all.
  CSHAPES_REQUIRE(*std::max_element(r.class_sizes.begin(), r.class_sizes.end()) >= o.retrieval.min_class_size,
                  r.data, ": no class has ", o.retrieval.min_class_size,
                  " shapes or more, so no shape can be a query (the measures need a class of at least "
                  "min_class_size; classes are the file names without trailing digits, or the manifest's or "
                  ".cla's)");
  std::vector<std::string> names, classes;
  for (const DatasetEntry& e : data.entries) {
    names.push_back(e.name);
    classes.push_back(e.class_name);
  }
  if (comm.is_root()) {
    write_classification(folder.path("classes.cla"), classification_from_labels(names, classes));
    r.inputs = dataset_checksums(r.resampled ? read_dataset(o.data, o.allow_outside) : data);
  }
  // cmds and SMACOF: each shape's geodesic matrix computed once for both, before their passes.
  const std::map<std::string, long> computed_ahead =
      precompute_shared_geodesic_forms(distance_options(o, r, folder, comm, ""), o.methods, &r.profile);
  std::set<std::string> unreadable;  // said once, not once per method
  for (const std::string& method : o.methods) {
    say(o.note, "== " + canonical_form_method_title(method) + ": canonical forms and ICP distances");
    const auto method_start = WallClock::now();
    const DatasetDistances distances = dataset_distances(distance_options(o, r, folder, comm, method));
    r.profile.insert(r.profile.end(), distances.profile.begin(), distances.profile.end());
    const Stopwatch measures;
    for (const ShapeFailure& f : distances.failures)
      if (!f.method.empty() || unreadable.insert(f.path).second) r.failures.push_back(f);
    const auto ahead = computed_ahead.find(method);
    RetrievalMethodResult m =
        method_counts(method, distances, ahead == computed_ahead.end() ? 0 : ahead->second);
    if (comm.is_root()) write_method_files(folder, o, distances, m);
    if (comm.is_root() && !o.two_stage_reference.empty()) m.exact = exact_measures(o, method);
    r.profile.push_back(stage_time("measures", method, measures));
    m.seconds = seconds_since(method_start);
    r.methods.push_back(std::move(m));
  }
  r.seconds = seconds_since(start);
  if (comm.is_root()) {
    json out = result_json(r);
    out["build"] = build_json();
    folder.write_json("retrieval.json", out);
  }
  return r;
}

void draw_retrieval_figures(RetrievalExperimentResult& r, const std::string& folder) {
  const std::string figures = (fs::path(folder) / "figures").string();
  const FigureFormat format = r.options.figure_format;
  const FigureRun drawn =
      draw_figure("retrieval_figures.py", {folder}, (fs::path(figures) / "pr").string(), format,
                  r.options.methods);
  r.figures.clear();
  if (!drawn.drawn) {
    r.figures_note = drawn.problem;
    return;
  }
  r.figures_note.clear();
  for (const char* name : {"pr", "per_class", "confusion"}) {
    const std::string file = figure_file_name(name, format);
    if (fs::exists(fs::path(figures) / file)) r.figures.push_back("figures/" + file);
  }
}

RetrievalExperimentResult retrieval_experiment(const RetrievalExperimentOptions& options) {
  const Communicator& comm = options.communicator ? *options.communicator : single_process();
  OutputRun output(options.out, "experiment retrieval", experiment_kept_folders(), options.force, &comm);
  start_outside_methods(options.out);
  RetrievalExperimentResult r = run_retrieval_experiment(options);
  if (!comm.is_root()) return r;
  if (options.figures) {
    const Stopwatch watch;
    draw_retrieval_figures(r, options.out);
    if (!r.figures_note.empty()) say(options.note, "no figures: " + r.figures_note);
    r.profile.push_back(stage_time("figures", "", watch));
    // retrieval.json again, with the figures' time in its profile (the figures read the first one).
    json out = result_json(r);
    out["build"] = build_json();
    ExperimentFolder(options.out).write_json("retrieval.json", out);
  } else {
    r.figures_note = "not requested (--no-draw)";
  }
  write_retrieval_report(r, options.out);
  finish_outside_methods(options.methods, options.out, options.note);
  output.commit();
  return r;
}

}  // namespace cshapes
