#include "cshapes/experiments/invariance_experiment.h"
#include "cshapes/experiments/invariance_experiment_detail.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <optional>
#include <set>

#include "cshapes/data/dataset.h"
#include "cshapes/experiments/figures.h"
#include "cshapes/experiments/invariance_transforms.h"
#include "cshapes/experiments/outside_methods_report.h"
#include "cshapes/matching/shape_distance.h"
#include "cshapes/mesh/io.h"
#include "cshapes/pipeline/experiment_kit.h"
#include "cshapes/pipeline/resampled_dataset.h"
#include "cshapes/support/error.h"
#include "cshapes/support/output_folder.h"
#include "cshapes/support/timing.h"

namespace cshapes {

using invariance_detail::MethodTally;
using invariance_detail::resolution_text;

namespace {

// A shape of the run: its dataset entry and its input mesh (empty when it could not be read).
struct RunShape {
  DatasetEntry entry;
  Mesh input;
  bool readable = false;
};

// Per shape (index into the run's shapes) and vertex count: its remesh.
using RemeshTable = std::map<std::pair<size_t, Index>, ResampledShape>;

// The per-(resolution, method) counters of the verdicts.
using Tallies = std::map<std::pair<Index, std::string>, MethodTally>;

void check_options(const InvarianceOptions& o) {
  using namespace invariance_limits;
  CSHAPES_REQUIRE(!o.methods.empty(), "experiment invariance: no method given");
  require_canonical_form_methods(o.methods, "experiment invariance");
  check_distinct(o.methods, "experiment invariance: methods");
  check_distinct(o.shapes, "experiment invariance: shapes");
  CSHAPES_REQUIRE(!o.vertices.empty(), "experiment invariance: no resolution given (0: the shapes as given)");
  for (Index n : o.vertices) {
    check_limit(kVertices, static_cast<double>(n), "experiment invariance");
    CSHAPES_REQUIRE(n == 0 || n >= kSmallestResolution,
                    "experiment invariance: vertices: expected 0 (as given) or ", kSmallestResolution,
                    " or more, got ", n);
  }
  std::vector<std::string> texts;
  for (Index n : o.vertices) texts.push_back(std::to_string(n));
  check_distinct(texts, "experiment invariance: vertices");
  check_limit(kSeeds, o.seeds, "experiment invariance");
  check_limit(kSeed, static_cast<double>(o.seed), "experiment invariance");
  check_limit(kToleranceFloor, o.tolerance_floor_percent, "experiment invariance");
  check_limit(kTolerancePose, o.tolerance_pose_percent, "experiment invariance");
}

// The dataset's shapes, or those of o.shapes (in the dataset's order; a name it lacks is refused), read;
// a file that cannot be read is recorded and left out (rethrown under strict).
std::vector<RunShape> read_shapes(const InvarianceOptions& o, InvarianceResult& result) {
  const Dataset data = read_dataset(o.data, o.allow_outside);
  add_records(result.failures, left_out_records(data.left_out, o.canon.strict), o.note);
  std::set<std::string> known;
  for (const DatasetEntry& e : data.entries) known.insert(e.name);
  for (const std::string& name : o.shapes)
    CSHAPES_REQUIRE(known.count(name), "experiment invariance: ", o.data, " has no shape named '", name, "'");
  const std::set<std::string> only(o.shapes.begin(), o.shapes.end());
  std::vector<RunShape> shapes;
  for (const DatasetEntry& e : data.entries) {
    if (!only.empty() && !only.count(e.name)) continue;
    RunShape s;
    s.entry = e;
    try {
      s.input = read_mesh(e.path);
      s.readable = true;
    } catch (const Error& error) {
      if (o.canon.strict) throw;
      result.failures.push_back(read_failure(e.name, e.path, error));
      say(o.note, "  " + describe(result.failures.back()));
    }
    shapes.push_back(std::move(s));
  }
  std::vector<DatasetEntry> chosen;
  for (const RunShape& s : shapes) chosen.push_back(s.entry);
  add_records(result.failures, same_content_records(chosen), o.note);
  return shapes;
}

// The vertex count of a remesh at `factor` × a reference of `vertices` vertices.
Index remesh_target(Index vertices, double factor) {
  return std::max<Index>(4, std::llround(factor * static_cast<double>(vertices)));
}

// Every remesh the run needs (each resolution's reference, and the 0.8× and 1.2× remeshes of the input), each
// vertex count once for every shape that needs it (resample_dataset: cached, written to OUT/resampled/N).
RemeshTable remesh_shapes(const std::vector<RunShape>& shapes, const InvarianceOptions& o,
                          const ExperimentFolder& folder, std::vector<ShapeFailure>& failures) {
  std::map<Index, std::set<size_t>> needed;  // vertex count → shapes
  for (Index resolution : o.vertices)
    for (size_t i = 0; i < shapes.size(); ++i) {
      if (!shapes[i].readable) continue;
      if (resolution > 0) needed[resolution].insert(i);
      const Index base = resolution > 0 ? resolution : shapes[i].input.num_vertices();
      for (double factor : kInvarianceRemeshFactors) needed[remesh_target(base, factor)].insert(i);
    }
  RemeshTable table;
  for (const auto& [target, which] : needed) {
    Dataset d;
    d.source = o.data;
    std::map<std::string, size_t> index_of;
    for (size_t i : which) {
      d.entries.push_back(shapes[i].entry);
      index_of[shapes[i].entry.name] = i;
    }
    ResampleOptions ro;
    ro.vertices = target;
    const ResampledDataset r = resample_dataset(d, ro, folder.path("resampled/" + std::to_string(target)),
                                                folder.cache("remeshed"), nullptr, o.note);
    add_records(failures, resample_records(r), o.note);
    for (const ResampledShape& s : r.shapes) table[{index_of.at(s.name), target}] = s;
  }
  return table;
}

// 1 or 0 when the method tests convergence (Coulomb's `converged`, SMACOF's stop reason), else −1.
int convergence(const CanonicalForm& form) {
  const nlohmann::json& d = form.details;
  if (d.contains("converged") && d["converged"].is_boolean()) return d["converged"].get<bool>() ? 1 : 0;
  if (d.contains("smacof") && d["smacof"].is_object() && d["smacof"].contains("stop_reason"))
    return d["smacof"]["stop_reason"] != "max iterations" ? 1 : 0;
  return -1;
}

// One mesh's forms by every method: none where a method failed (its record in `failures`, said). All methods
// in one call first (MDS methods share their geodesic matrix); when one fails, each other method alone.
// keep_kept: keep the records of forms that were kept (geodesic fallbacks, form quality) too.
std::vector<std::optional<CachedForm>> forms_by_method(const DiskCache& cache, const Mesh& mesh,
                                                       const std::string& mesh_name, const std::string& label,
                                                       bool keep_kept, const InvarianceOptions& o,
                                                       std::vector<ShapeFailure>& failures) {
  std::vector<ShapeFailure> records;
  std::vector<std::optional<CachedForm>> out(o.methods.size());
  auto all =
      shape_canonical_forms(cache, mesh, options_per_method(o.canon, o.methods, mesh_name), label, records);
  if (all) {
    for (size_t k = 0; k < o.methods.size(); ++k) out[k] = std::move((*all)[k]);
  } else {
    const std::string failed = records.empty() ? "" : records.back().method;
    for (size_t k = 0; k < o.methods.size(); ++k) {
      if (o.methods[k] == failed) continue;
      auto one = shape_canonical_forms(cache, mesh, options_per_method(o.canon, {o.methods[k]}, mesh_name),
                                       label, records);
      if (one) out[k] = std::move(one->front());
    }
  }
  for (const ShapeFailure& r : records) {
    if (!r.left_out() && !keep_kept) continue;
    failures.push_back(r);
    say(o.note, "  " + describe(r));
  }
  return out;
}

// One shape at one resolution: its reference mesh, and the remeshes of its input reported apart.
struct ShapeCase {
  const RunShape* shape = nullptr;
  Index resolution = 0;
  Mesh reference;
  std::string reference_name;  // the name methods are given: "cat0", "cat0-v1000"
  struct Remesh {
    std::string transformation;  // "remesh-0.8"
    Mesh mesh;
    std::string name;  // "cat0-v800"
  };
  std::vector<Remesh> remeshes;
};

// "cat0 (1000 vertices, renumber seed 2)": a form's name in the failures.
std::string case_label(const ShapeCase& c, const std::string& what) {
  return c.shape->entry.name + " (" + resolution_text(c.resolution) + (what.empty() ? "" : ", " + what) + ")";
}

// The shape's case at a resolution from the remesh table.
ShapeCase shape_case(const RunShape& s, size_t index, Index resolution, const RemeshTable& remeshes) {
  ShapeCase c;
  c.shape = &s;
  c.resolution = resolution;
  c.reference = s.input;
  c.reference_name = s.entry.name;
  if (resolution > 0) {
    const ResampledShape& r = remeshes.at({index, resolution});
    if (r.remeshed) c.reference = read_mesh(r.file);  // else kept as given: its record says so
    c.reference_name += "-v" + std::to_string(resolution);
  }
  const Index base = resolution > 0 ? resolution : s.input.num_vertices();
  for (double factor : kInvarianceRemeshFactors) {
    const Index target = remesh_target(base, factor);
    const ResampledShape& r = remeshes.at({index, target});
    if (!r.remeshed) continue;  // kept at its own resolution: no remesh to compare (its record says why)
    c.remeshes.push_back({"remesh-" + invariance_detail::factor_text(factor), read_mesh(r.file),
                          s.entry.name + "-v" + std::to_string(target)});
  }
  return c;
}

// Measures one shape at one resolution: result.rows, the tallies, and its reference forms (for the pose
// pairs).
std::vector<std::optional<Points>> measure_case(const ShapeCase& c, const DiskCache& cache,
                                                const InvarianceOptions& o, InvarianceResult& result,
                                                Tallies& tallies, const std::function<void()>& step) {
  const std::string& name = c.shape->entry.name;
  const auto reference =
      forms_by_method(cache, c.reference, c.reference_name, case_label(c, ""), true, o, result.failures);
  step();
  std::vector<std::optional<Points>> forms(o.methods.size());
  std::vector<int> reference_converged(o.methods.size(), -1);
  for (size_t k = 0; k < o.methods.size(); ++k) {
    if (!reference[k]) continue;
    forms[k] = reference[k]->form.X;
    reference_converged[k] = convergence(reference[k]->form);
    tallies[{c.resolution, o.methods[k]}].count_convergence(reference_converged[k]);
  }
  auto add_row = [&](size_t k, const std::string& transformation, bool exact, long long seed, Index vertices,
                     const FormChange& change, const CanonicalForm& form) {
    InvarianceRow row;
    row.resolution = c.resolution;
    row.shape = name;
    row.method = o.methods[k];
    row.transformation = transformation;
    row.exact = exact;
    row.seed = seed;
    row.vertices = vertices;
    row.rmse = change.rmse;
    row.hausdorff = change.hausdorff;
    row.converged = convergence(form);
    row.reference_converged = reference_converged[k];
    row.seconds = form.precompute_seconds + form.solve_seconds;
    result.rows.push_back(row);
    tallies[{c.resolution, o.methods[k]}].count_convergence(row.converged);
  };
  for (const invariance_detail::ExactCase& e : invariance_detail::exact_cases(o)) {
    const TransformedMesh t = transform_mesh(c.reference, e.transform, e.seed);
    const std::string what = e.name(true);
    const auto transformed = forms_by_method(cache, t.mesh, c.reference_name + "-" + e.name(false),
                                             case_label(c, what), false, o, result.failures);
    step();
    for (size_t k = 0; k < o.methods.size(); ++k) {
      if (!reference[k]) continue;
      if (!transformed[k]) {
        // A forms-door method lacks the forms of the meshes made here until its user computes them
        // (OUT/forms-needed): not measured, not a failure of the method.
        MethodTally& tally = tallies[{c.resolution, o.methods[k]}];
        ++(canonical_form_method(o.methods[k]).door == "forms" ? tally.missing_forms : tally.failed_forms);
        continue;
      }
      add_row(k, to_string(e.transform), true, is_seeded(e.transform) ? static_cast<long long>(e.seed) : -1,
              t.mesh.num_vertices(), exact_form_change(*forms[k], transformed[k]->form.X, t),
              transformed[k]->form);
    }
  }
  for (const ShapeCase::Remesh& r : c.remeshes) {
    const auto other =
        forms_by_method(cache, r.mesh, r.name, case_label(c, r.transformation), true, o, result.failures);
    step();
    for (size_t k = 0; k < o.methods.size(); ++k)
      if (reference[k] && other[k])
        add_row(k, r.transformation, false, -1, r.mesh.num_vertices(),
                aligned_form_change(*forms[k], other[k]->form.X, o.icp), other[k]->form);
  }
  say(o.note, invariance_detail::case_note(c.shape->entry.name, c.resolution, result.rows, o.methods));
  return forms;
}

// Every pair of clean poses of one class at one resolution, by every method with both reference forms.
void measure_pose_pairs(const std::vector<RunShape>& shapes, Index resolution,
                        const std::vector<std::vector<std::optional<Points>>>& forms,
                        const InvarianceOptions& o, InvarianceResult& result) {
  for (size_t i = 0; i < shapes.size(); ++i)
    for (size_t j = i + 1; j < shapes.size(); ++j) {
      const DatasetEntry& a = shapes[i].entry;
      const DatasetEntry& b = shapes[j].entry;
      if (a.class_name != b.class_name || a.noisy || b.noisy || forms[i].empty() || forms[j].empty())
        continue;
      for (size_t k = 0; k < o.methods.size(); ++k) {
        if (!forms[i][k] || !forms[j][k]) continue;
        const ShapeDistance d = aligned_shape_distance(*forms[i][k], *forms[j][k], o.icp);
        const double diagonal =
            0.5 * (finite_bbox_diagonal(*forms[i][k]) + finite_bbox_diagonal(*forms[j][k]));
        result.pose_pairs.push_back({resolution, o.methods[k], a.name, b.name, a.class_name,
                                     d.rmse / diagonal, d.hausdorff / diagonal});
      }
    }
}

}  // namespace

InvarianceResult run_invariance_experiment(const InvarianceOptions& o) {
  const auto start = WallClock::now();
  check_options(o);
  const ExperimentFolder folder(o.out);
  const DiskCache cache = folder.cache("forms");
  InvarianceResult result;
  result.resolutions = o.vertices;
  result.methods = o.methods;
  const std::vector<RunShape> shapes = read_shapes(o, result);
  for (const RunShape& s : shapes) result.shapes.push_back(s.entry.name);
  say(o.note, detail::concat("experiment invariance: ", shapes.size(), " shapes, ", o.vertices.size(),
                             o.vertices.size() == 1 ? " resolution, " : " resolutions, ", o.methods.size(),
                             " methods"));
  const RemeshTable remeshes = remesh_shapes(shapes, o, folder, result.failures);
  long usable = 0;
  for (const RunShape& s : shapes) usable += s.readable;
  const double total = static_cast<double>(usable) * static_cast<double>(o.vertices.size()) *
                       static_cast<double>(invariance_detail::exact_cases(o).size() + 3);
  double done = 0;
  const std::function<void()> step = [&] {
    done += 1;
    if (o.progress) o.progress("invariance", done, total);
  };
  Tallies tallies;
  for (Index resolution : o.vertices) {
    std::vector<std::vector<std::optional<Points>>> forms(shapes.size());
    for (size_t i = 0; i < shapes.size(); ++i) {
      if (!shapes[i].readable) continue;
      forms[i] =
          measure_case(shape_case(shapes[i], i, resolution, remeshes), cache, o, result, tallies, step);
    }
    measure_pose_pairs(shapes, resolution, forms, o, result);
  }
  invariance_detail::summarise(o, tallies, result);
  result.seconds = seconds_since(start);
  invariance_detail::write_data_files(folder, o, result);
  return result;
}

void draw_invariance_figure(InvarianceResult& result, const InvarianceOptions& options) {
  result.figure.clear();
  if (!options.figure) {
    result.figure_problem = "not requested (--no-draw)";
    return;
  }
  if (result.rows.empty()) {
    result.figure_problem = "no form was compared";
    return;
  }
  const FigureRun drawn =
      draw_figure("invariance_figure.py", {options.out}, ExperimentFolder(options.out).path("invariance"),
                  options.figure_format, options.methods);
  if (drawn.drawn) result.figure = figure_file_name("invariance", options.figure_format);
  result.figure_problem = drawn.problem;
}

InvarianceResult invariance_experiment(const InvarianceOptions& options) {
  OutputRun output(options.out, "experiment invariance", experiment_kept_folders(), options.force);
  start_outside_methods(options.out);
  InvarianceResult result = run_invariance_experiment(options);
  draw_invariance_figure(result, options);
  // The JSON again, with the figure's outcome.
  ExperimentFolder(options.out).write_json("invariance.json", invariance_json(result, options));
  write_invariance_report(result, options);
  finish_outside_methods(options.methods, options.out, options.note, "invariance.md");
  output.commit();
  return result;
}

}  // namespace cshapes
