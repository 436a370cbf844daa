#include "cshapes/experiments/paper_experiment.h"
#include "cshapes/experiments/paper_experiment_detail.h"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <map>
#include <nlohmann/json.hpp>
#include <optional>
#include <set>
#include <sstream>

#include "cshapes/support/format.h"
#include "cshapes/support/atomic_file.h"
#include "cshapes/data/dataset.h"
#include "cshapes/support/error.h"
#include "cshapes/mesh/io.h"
#include "cshapes/mesh/mesh_defects.h"
#include "cshapes/mesh/mesh_repair.h"
#include "cshapes/mesh/rigid_transform.h"
#include "cshapes/support/timing.h"
#include "cshapes/support/output_folder.h"
#include "cshapes/data/topological_noise.h"
#include "cshapes/eval/correspondence_error.h"
#include "cshapes/eval/distance_csv.h"
#include "cshapes/eval/pairwise_distances.h"
#include "cshapes/eval/retrieval.h"
#include "cshapes/experiments/figures.h"
#include "cshapes/experiments/outside_methods_report.h"
#include "cshapes/pipeline/outside_methods.h"
#include "cshapes/support/threads.h"
#include "cshapes/experiments/paper_figures.h"
#include "cshapes/experiments/paper_report.h"
#include "cshapes/matching/icp.h"
#include "cshapes/matching/shape_distance.h"
#include "cshapes/pipeline/distributed.h"
#include "cshapes/pipeline/experiment_kit.h"
#include "cshapes/pipeline/glued_meshes.h"
#include "cshapes/pipeline/shape_failures.h"

namespace cshapes {

namespace fs = std::filesystem;
using nlohmann::json;
using paper_detail::ExperimentRun;
using paper_detail::figure_stage;
using paper_detail::MethodForms;
using paper_detail::noise_stage;
using paper_detail::point_map_stage;
using paper_detail::retrieval_stage;
using paper_detail::Shape;

namespace {

// The method options of one method, named after the shape's file (for messages).
CanonicalFormOptions method_options(const PaperExperimentOptions& o, const std::string& method,
                                    const std::string& name) {
  CanonicalFormOptions co = o.canon;
  co.method = method;
  co.name = name;
  co.progress = polls_of(o.canon.progress);  // the stop, not per-form reports (the run reports per shape)
  return co;
}

// Reads a mesh as it is (lenient) and works out, per method, what its repair will do (one line each on the
// note channel). Throws when a method cannot use it (too few vertices left, or --strict and a repair is
// needed); the caller skips the file then, or stops under --strict.
void check_shape(Shape& s, const std::string& path, const PaperExperimentOptions& o) {
  const MeshDefects defects = mesh_defects(s.mesh);
  s.defects = defects.summary();
  std::set<std::string> said;
  for (const std::string& m : o.methods) {
    RepairedMesh r = repair_for_canonical_form(s.mesh, method_options(o, m, path));
    s.repairs[m] = r.text;
    if (r.changed()) s.untouched = false;
    if (r.changed() && said.insert(r.text).second) say(o.note, r.text);
  }
  if (!s.mesh.is_point_cloud() && repair_for(s.mesh, MeshRequirements::manifold_surface()).changed())
    s.untouched = false;
}

void load_and_check(Shape& s, const std::string& path, const PaperExperimentOptions& o) {
  s.mesh = read_mesh(path);
  check_shape(s, path, o);
}

// The folder where corres/NAME.vts would be: the dataset folder, or the manifest's folder.
std::string correspondence_folder(const std::string& data) {
  fs::path p(data);
  if (fs::is_regular_file(p)) p = p.parent_path();
  return (p / "corres").string();
}

// Glued here: the noisy shape and its pairs, through the glued-mesh cache every experiment shares. Throws
// the glue's error when the pose offers too few spots (the caller tries the next pose).
Shape make_noisy(const Shape& source, const PaperExperimentOptions& o, const DiskCache& cache, int index) {
  TopologicalNoiseOptions no;
  no.glue_count = o.glue;
  no.seed = o.seed + static_cast<std::uint64_t>(index);
  no.relax_steps = 3;  // shapes with few almost-touching spots: widen the gap rather than give up
  no.geodesic.progress = o.canon.progress;  // the run's stop, polled before each geodesic test
  GluedMesh g = cached_glued_mesh(cache, source.mesh, no);
  if (!g.ok()) throw Error(g.error);
  Shape s;
  s.name = source.name + "_noisy";
  s.class_name = source.class_name;
  s.source_name = source.name;
  s.noisy = true;
  s.mesh = std::move(g.mesh);
  s.glued = std::move(g.glued);
  s.key = mesh_content_key(s.mesh);
  return s;
}

// Choosing the shapes of the run: per class, the clean poses and the dataset's noisy shapes, and noisy shapes
// glued here (through the shared glued-mesh cache). write_files: the glued shapes' files under out/shapes
// (rank 0 only).
struct ShapeSelection {
  const PaperExperimentOptions& o;
  const DiskCache& noise_cache;
  std::vector<PaperReport::Skipped>& skipped;
  bool write_files;
  std::string corres;  // where corres/NAME.vts would be
  std::vector<Shape> shapes;
  int glued_count = 0;

  // A shape no method can use (unreadable, too few vertices after repair) is skipped with its reason, and
  // the next pose takes its place; under --strict a mesh needing repair stops the run instead.
  std::optional<Shape> try_load(const DatasetEntry& e, const std::string& cls, bool in_retrieval) {
    Shape s;
    s.name = e.name;
    s.class_name = cls;
    s.source_path = e.path;
    s.noisy = e.noisy;
    s.in_retrieval = in_retrieval;
    if (o.canon.progress) o.canon.progress("", 0, 0);  // a poll (support/progress.h): a stop between shapes
    try {
      load_and_check(s, e.path, o);
    } catch (const WriteError&) {
      throw;  // the run's own files: never one shape's failure
    } catch (const Error& error) {
      if (o.canon.strict) throw;
      say(o.note, std::string("skipped: ") + error.what());
      skipped.push_back({e.path, error.what()});
      return std::nullopt;
    }
    s.key = mesh_content_key(s.mesh);
    std::string vts = corres + "/" + e.name + ".vts";
    if (fs::exists(vts)) s.vts = vts;
    return s;
  }

  Shape load(const DatasetEntry& e, const std::string& cls, bool in_retrieval) {
    std::optional<Shape> s = try_load(e, cls, in_retrieval);
    if (!s) fail(e.path, ": cannot be used (see above)");
    return std::move(*s);
  }

  // One class: its clean poses (and the data's noisy shapes) in the retrieval set, then the noisy shapes
  // glued here.
  void select_class(const Dataset& data, const std::string& cls) {
    std::vector<const DatasetEntry*> clean, noisy;
    for (const DatasetEntry& e : data.entries)
      if (e.class_name == cls) (e.noisy ? noisy : clean).push_back(&e);
    const size_t want_clean = o.poses_per_class <= 0 ? clean.size() : static_cast<size_t>(o.poses_per_class);
    size_t n_clean = 0;
    for (size_t k = 0; k < clean.size() && n_clean < want_clean;) {
      if (auto s = try_load(*clean[k], cls, true)) {
        shapes.push_back(std::move(*s));
        ++n_clean;
        ++k;
      } else {
        clean.erase(clean.begin() + static_cast<long>(k));
      }
    }
    const bool every_pose = o.noisy_per_class == PaperExperimentOptions::kNoisyEveryPose;
    const size_t want_noisy = every_pose ? noisy.size() : static_cast<size_t>(std::max(o.noisy_per_class, 0));
    size_t from_data = 0;
    for (size_t k = 0; k < noisy.size() && from_data < want_noisy; ++k)
      if (auto s = try_load(*noisy[k], cls, true)) {
        shapes.push_back(std::move(*s));
        ++from_data;
      }
    glue_noisy_shapes(cls, clean, n_clean, from_data);
  }

  void glue_noisy_shapes(const std::string& cls, const std::vector<const DatasetEntry*>& clean,
                         size_t n_clean, size_t from_data) {
    const bool every_pose = o.noisy_per_class == PaperExperimentOptions::kNoisyEveryPose;
    // Noisy shapes made here: from the poses not in the retrieval set if there are any (so the noisy shape is
    // a pose of its own, as in the paper), else from the retrieval poses. Their clean source is kept as a
    // reference for the noise measurement. With noisy shapes from the data, one more is glued from the first
    // pose, for the measurement only.
    // Every pose (kNoisyEveryPose): one glued version of each clean pose, whatever the data holds.
    int to_make = every_pose ? static_cast<int>(clean.size())
                             : std::max(o.noisy_per_class, 0) - static_cast<int>(from_data);
    bool measurement_only = false;
    if (to_make <= 0 && !clean.empty() && o.noisy_per_class > 0) {
      to_make = 1;
      measurement_only = true;
    }
    // Candidate sources in order: the spare poses, then the retrieval poses; a pose that offers too few
    // almost-touching spots is skipped (said in a note) and the next one tried.
    std::vector<size_t> candidates;
    for (size_t k = n_clean; k < clean.size(); ++k) candidates.push_back(k);
    for (size_t k = 0; k < n_clean; ++k) candidates.push_back(k);
    size_t next_candidate = 0;
    for (int k = 0; k < to_make; ++k) {
      bool made = false;
      while (!made && next_candidate < candidates.size()) {
        const size_t c = candidates[next_candidate++];
        const DatasetEntry& src = *clean[c];
        Shape source;
        auto it =
            std::find_if(shapes.begin(), shapes.end(), [&](const Shape& s) { return s.name == src.name; });
        const bool loaded = it != shapes.end();
        try {
          source = loaded ? *it : load(src, cls, false);
        } catch (const WriteError&) {
          throw;  // the run's own files: never one shape's failure
        } catch (const Error& e) {
          continue;  // already said and listed as skipped
        }
        say(o.note, "gluing " + std::to_string(o.glue) + " spots of " + src.name);
        Shape s;
        try {
          s = make_noisy(source, o, noise_cache, glued_count++);
        } catch (const WriteError&) {
          throw;  // the run's own files: never one shape's failure
        } catch (const Error& e) {
          say(o.note, std::string("  skipped: ") + e.what());
          continue;
        }
        if (!loaded) shapes.push_back(source);  // kept as the reference of the noise measurement
        s.in_retrieval = !measurement_only;
        s.source_path = (fs::path(o.out) / "shapes" / (s.name + ".off")).string();
        check_shape(s, s.source_path, o);
        if (write_files) {
          write_mesh(s.source_path, s.mesh);
          write_file_atomically((fs::path(o.out) / "shapes" / (s.name + ".glued.json")).string(),
                                [&](std::ostream& out) {
                                  out << json{{"glued_vertices", s.glued}}.dump() << '\n';
                                });
        }
        shapes.push_back(std::move(s));
        made = true;
      }
      if (!made)
        say(o.note,
            "class " + cls + ": no pose offers " + std::to_string(o.glue) + " glues; fewer noisy shapes");
    }
  }
};

// left_out: the records of the folder's entries that are no shape (under strict, the first one throws).
std::vector<Shape> select_shapes(const PaperExperimentOptions& o, const DiskCache& noise_cache,
                                 std::vector<PaperReport::Skipped>& skipped, bool write_files,
                                 std::vector<ShapeFailure>& left_out) {
  const Dataset data = read_dataset(o.data, o.allow_outside);
  left_out = left_out_records(data.left_out, o.canon.strict);
  ShapeSelection selection{o, noise_cache, skipped, write_files, correspondence_folder(o.data), {}, 0};
  for (const std::string& cls : data.classes) selection.select_class(data, cls);
  CSHAPES_REQUIRE(!selection.shapes.empty(), o.data, ": no shapes selected");
  return std::move(selection.shapes);
}

// only: when non-null, the shapes to canonize (the others are left empty); write_files: the forms' PLY files
// under out/canon and progress on o.progress (rank 0's full pass). A shape whose form fails by any method
// (pipeline/shape_failures.h) has failed[i] set, its record in `failures` and no forms; under --strict the
// error ends the run.
std::map<std::string, MethodForms> canonize_all(const std::vector<Shape>& shapes,
                                                const PaperExperimentOptions& o, const DiskCache& cache,
                                                PaperExperimentSummary& summary, std::vector<char>& failed,
                                                std::vector<ShapeFailure>& failures,
                                                const std::vector<char>* only = nullptr,
                                                bool write_files = true) {
  std::map<std::string, MethodForms> result;
  for (const std::string& m : o.methods) {
    result[m].forms.resize(shapes.size());
    result[m].keys.resize(shapes.size());
  }
  failed.assign(shapes.size(), 0);
  const auto start = WallClock::now();
  std::vector<ShapeAhead> ahead;  // a command door's programs, several at a time
  for (size_t i = 0; i < shapes.size(); ++i)
    if (!only || (*only)[i]) ahead.push_back({&shapes[i].mesh, shapes[i].source_path});
  for (const std::string& m : o.methods)
    if (is_command_door_method(m)) run_commands_ahead(cache, ahead, method_options(o, m, ""), refresh_threads());
  for (size_t i = 0; i < shapes.size(); ++i) {
    if (only && !(*only)[i]) continue;
    const Shape& s = shapes[i];
    // One geodesic matrix serves both MDS methods (on the mesh repaired for them).
    std::vector<CanonicalFormOptions> per_method;
    for (const std::string& m : o.methods) per_method.push_back(method_options(o, m, s.source_path));
    const size_t failures_before = failures.size();
    std::optional<std::vector<CachedForm>> computed =
        shape_canonical_forms(cache, s.mesh, per_method, s.name, failures);
    for (size_t k = failures_before; k < failures.size(); ++k) say(o.note, "  " + describe(failures[k]));
    if (!computed) {
      failed[i] = 1;
      continue;
    }
    for (size_t k = 0; k < o.methods.size(); ++k) {
      const std::string& m = o.methods[k];
      CanonicalForm f = std::move((*computed)[k].form);
      ((*computed)[k].cached ? summary.canonical_forms_cached : summary.canonical_forms_computed)++;
      result[m].keys[i] = (*computed)[k].key;
      if (!write_files) {
        result[m].forms[i] = std::move(f);
        continue;
      }
      // Write the form for users and for the figures.
      WriteOptions wo;
      if (f.torn.size() == s.mesh.num_vertices()) wo.scalars.push_back({"torn", f.torn});
      if (f.valid.size() == s.mesh.num_vertices() && f.valid.minCoeff() == 0)
        wo.scalars.push_back({"valid", f.valid});
      if (!s.glued.empty()) {
        Eigen::VectorXd glued = Eigen::VectorXd::Zero(s.mesh.num_vertices());
        for (int v : s.glued) glued[v] = 1;
        wo.scalars.push_back({"glued", glued});
      }
      write_mesh((fs::path(o.out) / "canon" / m / (s.name + ".ply")).string(), Mesh{f.X, s.mesh.F}, wo);
      result[m].forms[i] = std::move(f);
    }
    if (!write_files) continue;
    double elapsed = seconds_since(start);
    say(o.note, detail::concat("  ", s.name, " (", s.mesh.num_vertices(), " vertices) done; ", i + 1, "/",
                               shapes.size(), ", about ",
                               std::lround(elapsed / (i + 1) * (shapes.size() - i - 1)), " s left"));
    // After the shape's line, so that the stage's closing "100.0%" comes last.
    if (o.progress)
      o.progress("canonical forms", static_cast<double>(i + 1), static_cast<double>(shapes.size()));
  }
  return result;
}

// Marks failed the shapes whose form by some method is too far in size from that method's other forms for ICP
// to align at one scale (pipeline/shape_failures.h), each recorded once.
void leave_out_incomparable_sizes(ExperimentRun& run, std::vector<char>& failed) {
  for (const std::string& m : run.o.methods) {
    std::vector<const Points*> forms(run.shapes.size(), nullptr);
    for (size_t i = 0; i < run.shapes.size(); ++i)
      if (!failed[i]) forms[i] = &run.forms[m].forms[i].X;
    for (size_t i : forms_of_incomparable_size(forms)) {
      if (run.o.canon.strict) fail(run.shapes[i].name, ": ", incomparable_size_reason());
      failed[i] = 1;
      run.summary.failures.push_back(
          {run.shapes[i].name, run.shapes[i].source_path, m, "alignment", incomparable_size_reason(), ""});
      say(run.o.note, "  " + describe(run.summary.failures.back()));
    }
  }
}

// Leaves the shapes whose forms failed out of the run (failed[i], from canonize_all), by every method. A
// noisy shape glued here from a pose left out keeps its place in retrieval but loses its reference (no noise
// measurement, no figure cell).
void drop_failed_shapes(ExperimentRun& run, const std::vector<char>& failed) {
  if (std::find(failed.begin(), failed.end(), 1) == failed.end()) return;
  std::set<std::string> dropped;
  std::vector<Shape> kept;
  std::map<std::string, MethodForms> forms;
  for (size_t i = 0; i < run.shapes.size(); ++i) {
    if (failed[i]) {
      dropped.insert(run.shapes[i].name);
      continue;
    }
    for (auto& [m, mf] : run.forms) {
      forms[m].forms.push_back(std::move(mf.forms[i]));
      forms[m].keys.push_back(std::move(mf.keys[i]));
    }
    kept.push_back(std::move(run.shapes[i]));
  }
  for (Shape& s : kept)
    if (dropped.count(s.source_name)) {
      say(run.o.note,
          "  " + s.name + ": its clean pose " + s.source_name + " was left out; no noise measurement for it");
      s.source_name.clear();
    }
  run.shapes = std::move(kept);
  run.forms = std::move(forms);
}

// 1. Shapes. Rank 0 first (it glues the noisy shapes into the cache and writes them out); then the others,
// which find the glued shapes in the cache.
void select_stage(ExperimentRun& run) {
  const PaperExperimentOptions& o = run.o;
  const Communicator& comm = run.comm;
  PaperExperimentSummary& summary = run.summary;
  PaperReport& report = run.report;
  say(o.note, "== shapes from " + o.data);
  std::vector<ShapeFailure> left_out;
  if (comm.is_root()) run.shapes = select_shapes(o, run.misc_cache, report.skipped, true, left_out);
  comm.barrier();
  if (!comm.is_root()) run.shapes = select_shapes(o, run.misc_cache, report.skipped, false, left_out);
  for (const PaperReport::Skipped& k : report.skipped)
    summary.failures.push_back(read_failure(fs::path(k.file).stem().string(), k.file, Error(k.reason)));
  // Two queries of the data with the same bytes under different names: both stay in the retrieval set (a
  // public benchmark holds such pairs), and the run says so (stderr, report.md, the JSON).
  std::vector<DatasetEntry> queries;
  for (const Shape& s : run.shapes)
    if (s.in_retrieval && s.source_name.empty())
      queries.push_back({s.source_path, s.name, s.class_name, -1, s.noisy});
  add_records(summary.failures, same_content_records(queries), o.note);
  // The folder's entries that are no shape (a loop of links, a FIFO, a second file of one name): left out.
  add_records(summary.failures, left_out, o.note);
}

// 2. Canonical forms. Distributed: each rank first canonizes its share into the cache (longest first by
// expected cost); then every rank reads them all, and rank 0 writes them out. A shape whose form fails by
// any method is left out by every method (each rank meets the same failure in the full pass).
void canonical_form_stage(ExperimentRun& run) {
  const PaperExperimentOptions& o = run.o;
  const Communicator& comm = run.comm;
  PaperExperimentSummary& summary = run.summary;
  PaperReport& report = run.report;
  // Counted as the report counts them: the retrieval set, and the clean poses kept as references only.
  const long n = static_cast<long>(run.shapes.size()),
             references = std::count_if(run.shapes.begin(), run.shapes.end(),
                                        [](const Shape& s) { return !s.in_retrieval; });
  say(o.note, "== canonical forms (" + counted(n, "shape") +
                  (references == 0 ? ""
                                   : ": " + std::to_string(n - references) + " in the retrieval set, " +
                                         counted(references, "clean pose") + " kept as references") +
                  (comm.size() > 1 ? ", over " + std::to_string(comm.size()) + " ranks)" : ")"));
  auto t = WallClock::now();
  long computed_by_ranks = 0;
  std::vector<char> failed;
  if (comm.size() > 1) {
    std::vector<long> vertices;
    for (const Shape& s : run.shapes) vertices.push_back(static_cast<long>(s.mesh.num_vertices()));
    const std::vector<int> owner = canonical_form_owners(vertices, o.methods, comm.size());
    std::vector<char> mine(run.shapes.size(), 0);
    for (size_t i = 0; i < run.shapes.size(); ++i) mine[i] = owner[i] == comm.rank();
    PaperExperimentOptions quiet = o;
    quiet.progress = polls_of(o.progress);
    quiet.note = {};
    PaperExperimentSummary share;
    std::vector<ShapeFailure> said_in_the_full_pass;
    canonize_all(run.shapes, quiet, run.form_cache, share, failed, said_in_the_full_pass, &mine, false);
    computed_by_ranks = comm.sum(share.canonical_forms_computed);
  }
  run.forms =
      canonize_all(run.shapes, o, run.form_cache, summary, failed, summary.failures, nullptr, comm.is_root());
  // The forms the ranks computed were read from the cache in the full pass: count them as computed.
  summary.canonical_forms_computed += computed_by_ranks;
  summary.canonical_forms_cached -= computed_by_ranks;
  leave_out_incomparable_sizes(run, failed);
  drop_failed_shapes(run, failed);
  report.summary.failures = summary.failures;  // the figures choose among the shapes kept
  report.stage_seconds["canonical forms"] = seconds_since(t);
}

// The retrieval set (the shapes kept that are queries), its labels (labels.csv), and what the report says of
// every shape and of each method's cost.
void retrieval_set(ExperimentRun& run) {
  const PaperExperimentOptions& o = run.o;
  const Communicator& comm = run.comm;
  PaperExperimentSummary& summary = run.summary;
  PaperReport& report = run.report;
  const std::vector<Shape>& shapes = run.shapes;
  std::vector<int>& retrieval = run.retrieval;
  for (size_t i = 0; i < shapes.size(); ++i)
    if (shapes[i].in_retrieval) retrieval.push_back(static_cast<int>(i));
  summary.shapes = static_cast<int>(retrieval.size());
  for (int i : retrieval) {
    run.names.push_back(shapes[i].name);
    run.classes.push_back(shapes[i].class_name);
  }
  run.labels = labels_from_classes(run.classes, &run.class_names);
  if (comm.is_root()) {
    write_file_atomically((fs::path(o.out) / "labels.csv").string(), [&](std::ostream& out) {
      out << "shape,class,noisy,vertices,file\n";
      for (int i : retrieval)
        out << shapes[i].name << ',' << shapes[i].class_name << ',' << shapes[i].noisy << ','
            << shapes[i].mesh.num_vertices() << ',' << shapes[i].source_path << '\n';
    });
  }
  for (const Shape& s : shapes) {
    PaperReport::ShapeRow row{s.name,        s.class_name, s.noisy, s.in_retrieval, s.mesh.num_vertices(),
                              s.source_name, s.defects,    {}};
    for (const auto& [m, text] : s.repairs)
      if (!text.empty()) row.repairs[m] = text;
    report.shapes.push_back(row);
  }
  CSHAPES_REQUIRE(retrieval.size() >= 2, o.data, ": ", retrieval.size(),
                  " shapes left in the retrieval set after ", count_left_out(summary.failures),
                  " were left out; the experiment needs at least 2");
  const std::map<std::string, MethodForms>& forms = run.forms;
  for (const auto& [m, mf] : forms) {
    PaperReport::MethodCost cost;
    for (int i : retrieval) {
      cost.precompute.push_back(mf.forms[i].precompute_seconds);
      cost.solve.push_back(mf.forms[i].solve_seconds);
      cost.iterations.push_back(mf.forms[i].iterations);
      cost.peak_bytes.push_back(mf.forms[i].details.value("peak_memory_bytes", -1.0));
    }
    report.cost[m] = cost;
  }
}

}  // namespace

PaperReport run_paper_experiment(const PaperExperimentOptions& given) {
  const auto start = WallClock::now();
  CSHAPES_REQUIRE(!given.out.empty(), "experiment: --out is required");
  require_canonical_form_methods(given.methods, "experiment");
  ExperimentFolder folder(given.out);
  // --resample: the run reads the remeshed collection; the report names the data given.
  PaperExperimentOptions o = given;
  // Every form, figure and timing the run computes hears its stop (Ctrl-C in Python) without reporting.
  if (!o.canon.progress) o.canon.progress = polls_of(o.progress);
  ResampledDataset resampled;
  if (o.resample.vertices > 0) {
    resampled = resample_dataset(o.data, o.resample, folder.path("resampled"), folder.cache("remeshed"),
                                 o.communicator, o.note, o.allow_outside);
    o.data = resampled.data;
    o.allow_outside = true;  // the remeshed collection's manifest lists kept shapes by their own paths
  }
  ExperimentRun run(o);
  PaperExperimentSummary& summary = run.summary;
  PaperReport& report = run.report;
  report.options = given;
  report.resampled = given.resample.vertices > 0;
  report.resampling = resampled;
  const Communicator& comm = run.comm;
  add_records(summary.failures, resample_records(resampled), o.note);

  // 1.-2. The shapes and their canonical forms; the retrieval set.
  select_stage(run);
  canonical_form_stage(run);
  retrieval_set(run);

  // 3.-6. The measurements, each a stage of its own. Only the pairs of stage 3 are distributed: the other
  // ranks are done after them.
  retrieval_stage(run);
  if (!comm.is_root()) {
    summary.seconds = seconds_since(start);
    report.summary = summary;
    return std::move(report);
  }
  noise_stage(run);
  point_map_stage(run);
  figure_stage(run);

  // 7. Table 1.
  if (o.table1) {
    say(o.note, "== Table 1 (timings)");
    const auto t = WallClock::now();
    measure_table1(o, report, run.misc_cache);
    report.stage_seconds["table 1"] = seconds_since(t);
  }

  summary.seconds = seconds_since(start);
  report.summary = summary;
  return std::move(report);
}

void draw_paper_figures(PaperReport& report) {
  const std::string out = report.options.out;
  // The first figure of the run stands for all (draw_figure checks that it was written).
  if (report.figures.empty()) {
    report.figures_drawn = false;
    report.figures_note = "this run has no figure to draw";
    return;
  }
  const FigureRun drawn =
      draw_figure("paper_figures.py", {out}, (fs::path(out) / report.figures.front()).string(),
                  report.options.figure_format, report.options.methods,
                  renamed_stage(report.options.progress, "drawing the figures"));
  report.figures_drawn = drawn.drawn;
  report.figures_note = drawn.problem;
}

PaperExperimentSummary paper_experiment(const PaperExperimentOptions& options) {
  const auto start = WallClock::now();
  const Communicator& comm = options.communicator ? *options.communicator : single_process();
  OutputRun output(options.out, "experiment paper", experiment_kept_folders(), options.force, &comm);
  start_outside_methods(options.out);
  PaperReport report = run_paper_experiment(options);
  if (comm.is_root()) {
    if (options.draw) {
      say(options.note, "== figures");
      draw_paper_figures(report);
      if (!report.figures_drawn) say(options.note, "warning: no figures: " + report.figures_note);
      report.summary.figures_drawn = report.figures_drawn;
    } else {
      report.figures_note = "not requested (`--no-draw`); draw them with `python3 " +
                            (fs::path(plot_scripts_directory()) / "paper_figures.py").string() + " " +
                            shell_quote(options.out) + "`";
    }
    report.summary.seconds = seconds_since(start);
    write_paper_report(report, options.out);
    finish_outside_methods(options.methods, options.out, options.note);
  }
  output.commit();
  return report.summary;
}

}  // namespace cshapes
