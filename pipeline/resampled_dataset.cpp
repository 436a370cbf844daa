#include "cshapes/pipeline/resampled_dataset.h"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstdio>
#include <exception>
#include <filesystem>
#include <map>
#include <numeric>
#include <optional>
#include <set>

#include "cshapes/support/format.h"
#include "cshapes/support/atomic_file.h"
#include "cshapes/data/dataset.h"
#include "cshapes/support/distance_matrix.h"
#include "cshapes/support/error.h"
#include "cshapes/mesh/io.h"
#include "cshapes/mesh/mesh_repair.h"
#include "cshapes/support/option_fields.h"
#include "cshapes/support/threads.h"
#include "cshapes/mesh/remesh.h"
#include "cshapes/pipeline/experiment_kit.h"

namespace cshapes {

namespace fs = std::filesystem;
using nlohmann::json;

namespace {

// What remeshing needs (a manifold triangle mesh), and nothing more: every component is kept.
MeshRequirements remesh_requirements() {
  MeshRequirements r;
  r.single_component = false;
  r.manifold = true;
  r.no_degenerate_faces = true;
  return r;
}

// The remesh of one input and its measures, as cached: {V, F, input_vertices, hausdorff, min_angle_in,
// min_angle, mean_min_angle, note} or, when it is kept as it is, {kept: reason, input_vertices, min_angle_in}.
// polls: remesh()'s progress, which may throw to abandon the remesh (then nothing is cached).
json compute_remesh(const Mesh& input, const ResampleOptions& options, const std::string& path,
                    const ProgressFn& polls) {
  const AngleStats in = angle_stats(input);
  json value{{"input_vertices", input.num_vertices()}, {"min_angle_in", in.min_angle}};
  if (input.is_point_cloud()) {
    value["kept"] = "a point cloud (no faces to remesh)";
    return value;
  }
  RepairOptions ro;
  ro.name = path;
  ro.purpose = "remeshing (a manifold surface)";
  const RepairedMesh repaired = repair_for(input, remesh_requirements(), ro);
  RemeshOptions o;
  o.target_vertices = options.vertices;
  o.tolerance = options.tolerance;
  o.progress = polls;
  try {
    const RemeshResult r = remesh(repaired.mesh, o);
    const AngleStats out = angle_stats(r.mesh);
    value["V"] = points_to_json(r.mesh.V);
    value["F"] = faces_to_json(r.mesh.F);
    value["hausdorff"] = hausdorff_distance(input, r.mesh) / bbox_diagonal(input.V);
    value["min_angle"] = out.min_angle;
    value["mean_min_angle"] = out.mean_min_angle;
    value["note"] = repaired.text;
  } catch (const WriteError&) {
    throw;
  } catch (const Error& e) {
    value["kept"] = std::string("cannot be remeshed: ") + e.what();
  }
  return value;
}

// A remesh's key: the file's content and the options. Non-manifold inputs are remeshed too, their Hausdorff
// distance measured; the tag's version changes with what an entry holds, so entries under an older key are
// not found and are remeshed again, once (docs/design.md, "Caches").
std::string remesh_key(const std::string& path, const ResampleOptions& options) {
  return cache_key({"resampled-mesh-v2", file_content_hash(path), options_key(options)});
}

// remesh_key, or nothing when the file cannot be read (the reader downstream says why).
std::optional<std::string> remesh_key_of(const std::string& path, const ResampleOptions& options) {
  try {
    return remesh_key(path, options);
  } catch (const WriteError&) {
    throw;
  } catch (const Error&) {
    return std::nullopt;
  }
}

// The cached remesh of one file under its key (computed on a miss, polls: compute_remesh's); nothing when the
// file cannot be read (no key, or the reader failed: the reader downstream says why).
std::optional<json> cached_remesh(const DiskCache& cache, const std::optional<std::string>& key,
                                  const std::string& path, const ResampleOptions& options,
                                  const ProgressFn& polls, bool* was_cached) {
  if (!key) return std::nullopt;
  if (std::optional<json> hit = cache.get_json(*key)) {
    *was_cached = true;
    return hit;
  }
  Mesh input;
  try {
    input = read_mesh(path);
  } catch (const WriteError&) {
    throw;
  } catch (const Error&) {
    return std::nullopt;
  }
  json value = compute_remesh(input, options, path, polls);
  cache.put_json(*key, value);
  *was_cached = false;
  return value;
}

// The entries `which` (indices into d.entries) by file size, largest first; equal sizes in their order.
std::vector<size_t> largest_first(const Dataset& d, std::vector<size_t> which) {
  std::vector<std::uintmax_t> size(d.entries.size(), 0);
  for (size_t i : which) {
    std::error_code ec;
    size[i] = fs::file_size(d.entries[i].path, ec);
  }
  std::stable_sort(which.begin(), which.end(), [&](size_t a, size_t b) { return size[a] > size[b]; });
  return which;
}

// Each rank remeshes its share into the cache, silently: the largest files first, dealt round-robin. Returns
// the remeshes this rank computed.
long remesh_share(const Dataset& d, const ResampleOptions& options, const DiskCache& cache,
                  const Communicator& comm) {
  std::vector<size_t> all(d.entries.size());
  std::iota(all.begin(), all.end(), size_t{0});
  const std::vector<size_t> order = largest_first(d, std::move(all));
  long computed = 0;
  for (size_t k = static_cast<size_t>(comm.rank()); k < order.size(); k += static_cast<size_t>(comm.size())) {
    bool cached = true;
    const std::string& path = d.entries[order[k]].path;
    if (cached_remesh(cache, remesh_key_of(path, options), path, options, {}, &cached) && !cached) ++computed;
  }
  return computed;
}

ResampledShape shape_record(const DatasetEntry& e, const json& value, const std::string& file) {
  ResampledShape s;
  s.name = e.name;
  s.source = e.path;
  s.file = file;
  s.input_vertices = value.at("input_vertices").get<Index>();
  s.min_angle_in = value.at("min_angle_in").get<double>();
  if (value.contains("kept")) {
    s.vertices = s.input_vertices;
    s.note = "kept at its own resolution: " + value.at("kept").get<std::string>();
    return s;
  }
  s.remeshed = true;
  s.vertices = static_cast<Index>(value.at("V").size() / 3);
  s.hausdorff = value.at("hausdorff").get<double>();
  s.min_angle = value.at("min_angle").get<double>();
  s.mean_min_angle = value.at("mean_min_angle").get<double>();
  s.note = value.value("note", "");
  return s;
}

void write_resample_csv(const std::string& path, const ResampledDataset& r) {
  write_file_atomically(path, [&](std::ostream& out) {
    out << "shape,source,input_vertices,vertices,hausdorff_over_diagonal,min_angle_in_deg,min_angle_deg,"
           "mean_min_angle_deg,remeshed,cached,note\n";
    out.precision(9);
    for (const ResampledShape& s : r.shapes) {
      std::string note = s.note;
      std::replace(note.begin(), note.end(), ',', ';');
      out << s.name << ',' << s.source << ',' << s.input_vertices << ',' << s.vertices << ',' << s.hausdorff
          << ',' << s.min_angle_in << ',' << s.min_angle << ',' << s.mean_min_angle << ','
          << (s.remeshed ? 1 : 0) << ',' << (s.cached ? 1 : 0) << ',' << note << '\n';
    }
  });
}

// What one entry became: its manifest entry (the remesh, or the input as it is) and its record (none for a
// file that cannot be read).
struct ShapeOutcome {
  bool done = false;
  DatasetEntry entry;
  std::optional<ResampledShape> shape;
};

// One entry through the cache (computed on a miss; polls: compute_remesh's), its remesh written into `folder`
// when `writes` (the root's part).
ShapeOutcome resample_entry(const DatasetEntry& e, const std::optional<std::string>& key,
                            const ResampleOptions& options, const std::string& folder, const DiskCache& cache,
                            bool writes, const ProgressFn& polls) {
  ShapeOutcome outcome{true, e, std::nullopt};
  bool cached = false;
  const std::optional<json> value = cached_remesh(cache, key, e.path, options, polls, &cached);
  const bool remeshed = value && !value->contains("kept");
  outcome.entry.path =
      remeshed ? (fs::path(folder) / (e.name + ".off")).string() : fs::absolute(e.path).string();
  if (!value) return outcome;  // unreadable: listed as it is, the reader downstream says why
  outcome.shape = shape_record(e, *value, outcome.entry.path);
  outcome.shape->cached = cached;
  if (writes && remeshed)
    write_mesh(outcome.entry.path, Mesh{points_from_json(value->at("V")), faces_from_json(value->at("F"))});
  return outcome;
}

// The progress note of a shape, the k-th of n done: a line, and a second for what was repaired first.
std::vector<std::string> shape_notes(const ResampledShape& s, size_t k, size_t n) {
  if (!s.remeshed) return {"  " + s.name + ": " + s.note};
  // For people: three significant figures (report.md's table and resample.csv keep theirs).
  char line[256];
  std::snprintf(line, sizeof line,
                "  [%zu/%zu] %s: %ld -> %ld vertices, Hausdorff %.3g%% of the diagonal, "
                "smallest angle %.3g deg%s",
                k, n, s.name.c_str(), static_cast<long>(s.input_vertices), static_cast<long>(s.vertices),
                100 * s.hausdorff, s.min_angle, s.cached ? " (cached)" : "");
  std::vector<std::string> lines{line};
  if (!s.note.empty()) lines.push_back("    " + s.note);
  return lines;
}

// How many shapes to remesh at once: `wanted`, or fewer when the memory does not hold that many remeshes
// (remesh_memory_bytes each, by require_memory's rule); one at least (checked before any work).
int shapes_at_once(int wanted, Index vertices) {
  for (int threads = wanted; threads > 1; --threads) {
    try {
      require_memory(threads * remesh_memory_bytes(vertices), "remeshing shapes at once");
      return threads;
    } catch (const Error&) {
    }
  }
  return 1;
}

// One call's remeshing: each entry's outcome in the dataset's order, the notes said as shapes finish.
class ResampleRun {
 public:
  ResampleRun(const Dataset& d, const ResampleOptions& options, const std::string& folder,
              const DiskCache& cache, bool writes, const NoteFn& note)
      : d_(d), options_(options), folder_(folder), cache_(cache), writes_(writes), note_(note) {
    outcomes_.resize(d.entries.size());
    stop_polls_ = [this](const std::string&, double, double) {
      if (stop_) throw Cancelled();  // another shape failed or the note stopped the run: abandon this remesh
    };
  }

  // Single process: the first entry of each content, several at once (one per thread), the largest files
  // first, in blocks with the thread count chosen again before each (support/threads.h). The later entries
  // of a content are left to remesh_the_rest, which reads the first one's remesh from the cache as one
  // after the other would. The first failure is rethrown once every thread has stopped.
  void remesh_concurrently() {
    keys_.resize(d_.entries.size());
    std::set<std::string> keys_seen;
    std::vector<size_t> firsts;
    for (size_t i = 0; i < d_.entries.size(); ++i) {
      keys_[i] = remesh_key_of(d_.entries[i].path, options_);
      if (keys_[i] && keys_seen.insert(*keys_[i]).second) firsts.push_back(i);
    }
    keyed_ = true;
    const std::vector<size_t> order = largest_first(d_, std::move(firsts));
    const long count = static_cast<long>(order.size());
    const long block = std::max(32L, 16L * refresh_threads());
    for (long first = 0; first < count && !stop_; first += block) {
      const long last = std::min(count, first + block);
      const int wanted = static_cast<int>(std::min<long>(refresh_threads(), last - first));
      const int threads = shapes_at_once(wanted, options_.vertices);
#pragma omp parallel for schedule(dynamic, 1) num_threads(threads)
      for (long k = first; k < last; ++k) {
        if (stop_) continue;
        try {
          resample(order[static_cast<size_t>(k)], stop_polls_);
        } catch (...) {
          keep_error();
        }
      }
    }
    if (error_) std::rethrow_exception(error_);
  }

  // The entries not done yet, one after the other in the dataset's order: on ranks all of them (each read
  // from the cache the ranks filled), else the later entries of a content and the files with no key.
  void remesh_the_rest() {
    for (size_t i = 0; i < d_.entries.size(); ++i)
      if (!outcomes_[i].done) resample(i, {});
  }

  const std::vector<ShapeOutcome>& outcomes() const {
    return outcomes_;
  }

 private:
  void resample(size_t i, const ProgressFn& polls) {
    const DatasetEntry& e = d_.entries[i];
    ShapeOutcome outcome = resample_entry(e, keyed_ ? keys_[i] : remesh_key_of(e.path, options_), options_,
                                          folder_, cache_, writes_, polls);
    tell(outcome);
    outcomes_[i] = std::move(outcome);  // each thread its own entries: no race
  }

  // The shape's notes, one shape at a time; none once the run is stopping. What the note throws (a stop)
  // leaves the critical section before it propagates.
  void tell(const ShapeOutcome& outcome) {
    std::exception_ptr failure;
#pragma omp critical(cshapes_resample_notes)
    if (!stop_) {
      const size_t k = ++done_;
      try {
        if (outcome.shape)
          for (const std::string& line : shape_notes(*outcome.shape, k, d_.entries.size())) say(note_, line);
      } catch (...) {
        failure = std::current_exception();
      }
    }
    if (failure) std::rethrow_exception(failure);
  }

  void keep_error() {
#pragma omp critical(cshapes_resample_error)
    if (!error_) error_ = std::current_exception();
    stop_ = true;
  }

  const Dataset& d_;
  const ResampleOptions& options_;
  const std::string& folder_;
  const DiskCache& cache_;
  const bool writes_;
  const NoteFn& note_;
  std::vector<ShapeOutcome> outcomes_;
  std::vector<std::optional<std::string>> keys_;  // each entry's remesh_key_of, once keyed_
  bool keyed_ = false;
  size_t done_ = 0;  // entries done, the notes' k
  std::atomic<bool> stop_{false};
  std::exception_ptr error_;
  ProgressFn stop_polls_;  // the concurrent remeshes' polls: abandon when stop_
};

}  // namespace

ResampledDataset resample_dataset(const std::string& data, const ResampleOptions& options,
                                  const std::string& folder, const DiskCache& cache,
                                  const Communicator* communicator, const NoteFn& note, bool allow_outside) {
  CSHAPES_REQUIRE(options.vertices >= 4, "resample: expected at least 4 vertices, got ", options.vertices);
  return resample_dataset(read_dataset(data, allow_outside), options, folder, cache, communicator, note);
}

ResampledDataset resample_dataset(const Dataset& d, const ResampleOptions& options, const std::string& folder,
                                  const DiskCache& cache, const Communicator* communicator,
                                  const NoteFn& note) {
  CSHAPES_REQUIRE(options.vertices >= 4, "resample: expected at least 4 vertices, got ", options.vertices);
  // Checked here, before any work: inside remesh() the refusal would be each shape's, cached as "kept".
  require_memory(remesh_memory_bytes(options.vertices),
                 "resample: remeshing to " + std::to_string(options.vertices) + " vertices");
  const Communicator& comm = communicator ? *communicator : single_process();
  std::map<std::string, std::string> by_name;
  for (const DatasetEntry& e : d.entries) {
    const auto [it, fresh] = by_name.emplace(e.name, e.path);
    CSHAPES_REQUIRE(fresh, d.source, ": two shapes named '", e.name, "' (", it->second, " and ", e.path,
                    "): resampling writes one file per name");
  }
  long computed_by_ranks = 0;
  if (comm.size() > 1) {
    computed_by_ranks = comm.sum(remesh_share(d, options, cache, comm));
    comm.barrier();
  }
  ResampledDataset r;
  r.options = options;
  r.folder = folder;
  r.left_out = d.left_out;
  r.data = (fs::path(folder) / "manifest.csv").string();
  say(note, "== resampling " + std::to_string(d.entries.size()) + " shapes to about " +
                std::to_string(options.vertices) + " vertices (cached in " + cache.directory() + ")");
  ResampleRun run(d, options, folder, cache, comm.is_root(), note);
  if (comm.size() == 1) run.remesh_concurrently();
  run.remesh_the_rest();
  std::vector<DatasetEntry> entries;
  for (const ShapeOutcome& outcome : run.outcomes()) {
    entries.push_back(outcome.entry);
    if (!outcome.shape) continue;
    (outcome.shape->cached ? r.cached : r.computed)++;
    r.shapes.push_back(*outcome.shape);
  }
  // The ranks computed their shares: count those as computed (they were read from the cache above).
  if (comm.size() > 1) {
    r.computed = computed_by_ranks;
    r.cached = static_cast<long>(r.shapes.size()) - computed_by_ranks;
  }
  if (comm.is_root()) {
    write_manifest(r.data, entries);
    write_resample_csv((fs::path(folder) / "resample.csv").string(), r);
  }
  comm.barrier();  // the folder is complete before any rank reads it
  return r;
}

std::vector<ShapeFailure> resample_records(const ResampledDataset& r) {
  std::vector<ShapeFailure> records = left_out_records(r.left_out);
  for (const ResampledShape& s : r.shapes)
    if (!s.remeshed)
      records.push_back({s.name, s.source, "", "resample", s.note,
                         "not resampled to " + std::to_string(r.options.vertices) + " vertices, " + s.note +
                             " (" + std::to_string(s.input_vertices) + " vertices)"});
  return records;
}

std::string resampling_markdown(const ResampledDataset& r) {
  std::string text;
  char line[512];
  double worst_hausdorff = 0, smallest_angle = 180;
  Index fewest = 0, most = 0;
  int kept = 0;
  for (const ResampledShape& s : r.shapes) {
    if (!s.remeshed) {
      ++kept;
      continue;
    }
    worst_hausdorff = std::max(worst_hausdorff, s.hausdorff);
    smallest_angle = std::min(smallest_angle, s.min_angle);
    fewest = fewest == 0 ? s.input_vertices : std::min(fewest, s.input_vertices);
    most = std::max(most, s.input_vertices);
  }
  if (kept == static_cast<int>(r.shapes.size())) {
    // Nothing remeshed: no range of inputs, no Hausdorff distance, no angle to summarise.
    std::snprintf(
        line, sizeof line,
        "No shape could be remeshed to about %ld vertices: all %d kept at their own resolution (see "
        "the table).\n\n",
        static_cast<long>(r.options.vertices), kept);
  } else {
    std::snprintf(
        line, sizeof line,
        "Every shape was remeshed to about %ld vertices first (CGAL isotropic remeshing, mesh/remesh.h; "
        "inputs of %ld to %ld vertices; cached by content: %ld computed, %ld cached). Largest "
        "Hausdorff distance to the input %.3f%% of its bounding-box diagonal (symmetric, sampled at "
        "vertices, edge midpoints and face centroids); smallest triangle angle %.1f deg.%s\n\n",
        static_cast<long>(r.options.vertices), static_cast<long>(fewest), static_cast<long>(most), r.computed,
        r.cached, 100 * worst_hausdorff, smallest_angle,
        kept
            ? (" " + counted(kept, "shape") + " kept at their own resolution (see the table).").c_str()
            : "");
  }
  text += line;
  text += "| shape | input vertices | vertices | Hausdorff / diagonal | smallest angle (in → out) | mean smallest "
          "angle | note |\n|---|---:|---:|---:|---:|---:|---|\n";
  const double nan = std::numeric_limits<double>::quiet_NaN();
  for (const ResampledShape& s : r.shapes)
    text += "| " + s.name + " | " + std::to_string(s.input_vertices) + " | " + std::to_string(s.vertices) +
            " | " + percent(s.remeshed ? s.hausdorff : nan, 3) + " | " + fixed(s.min_angle_in, 1) + " → " +
            fixed(s.remeshed ? s.min_angle : nan, 1) + " | " + fixed(s.remeshed ? s.mean_min_angle : nan, 1) +
            " | " + s.note + " |\n";
  return text;
}

}  // namespace cshapes
