#include "cshapes/pipeline/dataset_distances.h"

#include "cshapes/support/timing.h"

#include <algorithm>
#include <filesystem>
#include <optional>

#include "cshapes/support/atomic_file.h"
#include "cshapes/data/dataset.h"
#include "cshapes/support/error.h"
#include "cshapes/mesh/io.h"
#include "cshapes/eval/candidate_pairs.h"
#include "cshapes/eval/distance_csv.h"
#include "cshapes/matching/icp.h"
#include "cshapes/matching/shape_distance.h"
#include "cshapes/pipeline/distributed.h"
#include "cshapes/pipeline/outside_methods.h"
#include "cshapes/pipeline/shape_failures.h"
#include "cshapes/support/threads.h"

namespace cshapes {

namespace {

// Distributed runs: each rank canonizes its share of the shapes (longest first by vertex count) into the
// cache, silently (the main pass reports every shape and every error). Returns the forms computed, summed
// over ranks.
long canonize_share(const Dataset& data, const DiskCache& cache, CanonicalFormOptions co,
                    const Communicator& comm) {
  const size_t n = data.entries.size();
  // Vertex counts, each rank reading every R-th mesh.
  std::vector<long> vertices(n, 0);
  for (size_t i = static_cast<size_t>(comm.rank()); i < n; i += static_cast<size_t>(comm.size())) {
    try {
      vertices[i] = static_cast<long>(read_mesh(data.entries[i].path).num_vertices());
    } catch (const Error&) {
      // the main pass says why
    }
  }
  comm.sum_to_all(vertices.data(), vertices.size());
  const std::vector<int> owner = canonical_form_owners(vertices, {co.method}, comm.size());
  co.note = {};
  co.progress = polls_of(co.progress);
  long computed = 0;
  for (size_t i = 0; i < n; ++i) {
    if (owner[i] != comm.rank() || vertices[i] == 0) continue;
    try {
      co.name = data.entries[i].path;
      bool cached = false;
      cached_canonical_form(cache, read_mesh(data.entries[i].path), co, &cached);
      if (!cached) ++computed;
    } catch (const WriteError&) {
      throw;  // the shared cache cannot be written: the run stops (the CLI ends every rank)
    } catch (const Error&) {
      // the main pass meets the same error and reports it (or stops, under strict)
    }
  }
  return comm.sum(computed);
}

// The canonical form of every shape of the dataset by options.canon (cached), in dataset order: forms and
// their cache keys appended, names, classes and counts into result; a shape that cannot be read or canonized
// is reported and skipped.
void dataset_forms(const Dataset& data, const DiskCache& cache, CanonicalFormOptions co,
                   const DatasetDistanceOptions& options, DatasetDistances& result, std::vector<Points>& forms,
                   std::vector<std::string>& keys) {
  // A command door's programs run several at a time (run_commands_ahead), a batch of shapes ahead of this
  // pass, whose meshes are read once for both.
  const int workers = is_command_door_method(co.method) ? refresh_threads() : 1;
  const size_t batch = workers > 1 ? static_cast<size_t>(4 * workers) : 1;
  std::vector<std::optional<Mesh>> meshes;  // the batch's meshes (none: unreadable, said in the pass)
  size_t batch_start = 0;
  for (size_t i = 0; i < data.entries.size(); ++i) {
    const DatasetEntry& e = data.entries[i];
    co.name = e.path;
    if (workers > 1 && i == batch_start + meshes.size()) {
      batch_start = i;
      meshes.clear();
      std::vector<ShapeAhead> ahead;
      for (size_t k = i; k < std::min(i + batch, data.entries.size()); ++k) {
        try {
          meshes.emplace_back(read_mesh(data.entries[k].path));
        } catch (const Error&) {
          meshes.emplace_back(std::nullopt);
        }
      }
      for (size_t k = 0; k < meshes.size(); ++k)
        if (meshes[k]) ahead.push_back({&*meshes[k], data.entries[i + k].path});
      run_commands_ahead(cache, ahead, co, workers);
    }
    Mesh mesh;
    std::optional<std::vector<CachedForm>> computed;
    const size_t failures_before = result.failures.size();
    try {
      std::optional<Mesh>* read = workers > 1 ? &meshes[i - batch_start] : nullptr;
      mesh = read && *read ? std::move(**read) : read_mesh(e.path);
    } catch (const Error& error) {
      if (co.strict) throw;
      result.failures.push_back(read_failure(e.name, e.path, error));
    }
    if (result.failures.size() == failures_before)
      computed = shape_canonical_forms(cache, mesh, {co}, e.name, result.failures);
    for (size_t k = failures_before; k < result.failures.size(); ++k)
      say(options.note, describe(result.failures[k]));
    if (!computed) {
      result.skipped.push_back(e.path);
      result.skipped_reasons.push_back(result.failures.back().reason);
      continue;
    }
    // A form ICP cannot take was left out by shape_canonical_forms (stage "alignment").
    CachedForm& form = computed->front();
    if (!form.form.repair_text.empty()) say(options.note, form.form.repair_text);
    const bool cached = form.cached;
    (cached ? result.forms_cached : result.forms_computed)++;
    result.form_seconds.push_back(form.form.precompute_seconds + form.form.solve_seconds);
    result.form_peak_bytes.push_back(form.form.details.value("peak_memory_bytes", -1.0));
    forms.push_back(std::move(form.form.X));
    keys.push_back(form.key);
    result.names.push_back(e.name);
    result.classes.push_back(e.class_name);
    say(options.note, "[" + std::to_string(i + 1) + "/" + std::to_string(data.entries.size()) + "] " +
                          e.name + (cached ? " (cached)" : ""));
  }
  // A form far in size from the others (one shape at 1e-100 among shapes at 1) is left out by name: ICP cannot
  // align it with them at one scale, and in the pairs it would end the whole run.
  std::vector<const Points*> pointers;
  for (const Points& X : forms) pointers.push_back(&X);
  const std::vector<size_t> incomparable = forms_of_incomparable_size(pointers);
  for (auto k = incomparable.rbegin(); k != incomparable.rend(); ++k) {
    const auto entry = std::find_if(data.entries.begin(), data.entries.end(),
                                    [&](const DatasetEntry& e) { return e.name == result.names[*k]; });
    if (co.strict) fail(entry->path, ": ", incomparable_size_reason());
    result.failures.push_back({result.names[*k], entry->path, co.method, "alignment", incomparable_size_reason(), ""});
    say(options.note, describe(result.failures.back()));
    result.skipped.push_back(entry->path);
    result.skipped_reasons.push_back(incomparable_size_reason());
    for (auto* list : {&result.names, &result.classes, &keys}) list->erase(list->begin() + static_cast<long>(*k));
    for (auto* list : {&result.form_seconds, &result.form_peak_bytes})
      list->erase(list->begin() + static_cast<long>(*k));
    forms.erase(forms.begin() + static_cast<long>(*k));
  }
}

// Two-stage retrieval's first stage: the descriptor distances of the forms (returned), each form's k nearest
// by them as its candidates, and those pairs as the only ones ICP aligns (po.only_pairs).
Eigen::MatrixXd two_stage_candidates(const std::vector<Points>& forms, const DatasetDistanceOptions& options,
                                     DatasetDistances& result, PairwiseDistanceOptions& po) {
  const int n = static_cast<int>(forms.size());
  std::vector<ShapeDescriptor> descriptors(static_cast<size_t>(n));
#pragma omp parallel for schedule(dynamic, 1)
  for (int i = 0; i < n; ++i)
    descriptors[static_cast<size_t>(i)] =
        shape_descriptor(finite_rows(forms[static_cast<size_t>(i)]), options.descriptor);
  Eigen::MatrixXd descriptor_distances = Eigen::MatrixXd::Zero(n, n);
  for (int i = 0; i < n; ++i)
    for (int j = i + 1; j < n; ++j)
      descriptor_distances(i, j) = descriptor_distances(j, i) =
          descriptor_distance(descriptors[static_cast<size_t>(i)], descriptors[static_cast<size_t>(j)]);
  result.two_stage.k = options.two_stage_k;
  result.two_stage.candidates = nearest_candidates(descriptor_distances, options.two_stage_k);
  po.only_pairs = candidate_pairs(result.two_stage.candidates);
  result.two_stage.pairs_aligned = static_cast<long>(po.only_pairs.size());
  return descriptor_distances;
}

// The recall of the candidates against the exact reference matrix, its rows and columns matched by name.
double reference_recall(const NamedDistances& reference, const DatasetDistanceOptions& options,
                        const DatasetDistances& result) {
  std::vector<Index> at;
  for (const std::string& name : result.names) {
    auto it = std::find(reference.names.begin(), reference.names.end(), name);
    CSHAPES_REQUIRE(it != reference.names.end(), options.reference, ": no shape '", name,
                    "' (the reference must be the exact matrix of the same dataset)");
    at.push_back(it - reference.names.begin());
  }
  const Index n = static_cast<Index>(at.size());
  Eigen::MatrixXd R(n, n);
  for (Index i = 0; i < n; ++i)
    for (Index j = 0; j < n; ++j) R(i, j) = reference.D(at[static_cast<size_t>(i)], at[static_cast<size_t>(j)]);
  return candidate_recall(R, result.two_stage.candidates);
}

}  // namespace

DatasetDistances dataset_distances(const DatasetDistanceOptions& options) {
  const Communicator& comm = options.communicator ? *options.communicator : single_process();
  CSHAPES_REQUIRE(comm.size() == 1 || !options.cache_dir.empty(), options.data,
                  ": a distributed run needs a cache folder (the ranks share their results through it)");
  CSHAPES_REQUIRE(options.two_stage_k >= 0, "two-stage k = ", options.two_stage_k, ", expected >= 0");
  CSHAPES_REQUIRE(options.resample.vertices == 0 || !options.cache_dir.empty(), options.data,
                  ": resampling needs a cache folder (the remeshed shapes are written there)");
  DatasetDistances result;
  Stopwatch watch;
  if (options.resample.vertices > 0)
    result.resampling = resample_dataset(
        options.data, options.resample,
        (std::filesystem::path(options.cache_dir) / ("resampled-" + std::to_string(options.resample.vertices)))
            .string(),
        DiskCache((std::filesystem::path(options.cache_dir) / "remeshed").string()), &comm, options.note,
        options.allow_outside);
  if (options.resample.vertices > 0) result.profile.push_back(stage_time("resample", "", watch));
  for (const ShapeFailure& record : resample_records(result.resampling)) {
    say(options.note, describe(record));
    result.failures.push_back(record);
  }
  watch.restart();
  // The resampled manifest (written here) lists the shapes kept as they were by their own paths.
  const Dataset data = options.resample.vertices > 0 ? read_dataset(result.resampling.data, true)
                                                     : read_dataset(options.data, options.allow_outside);
  // The folder's entries that are no shape (resampled: in resample_records above), then same-content pairs.
  add_records(result.failures, left_out_records(data.left_out, options.canon.strict), options.note);
  add_records(result.failures, same_content_records(data), options.note);
  // The reference is read before any work: a missing or malformed file fails now, not after the alignments.
  NamedDistances reference;
  if (options.two_stage_k > 0 && !options.reference.empty() && comm.is_root())
    reference = read_distance_csv(options.reference);
  for (const DatasetEntry& e : reference.names.empty() ? std::vector<DatasetEntry>{} : data.entries)
    CSHAPES_REQUIRE(
        std::find(reference.names.begin(), reference.names.end(), e.name) != reference.names.end(),
        options.reference, ": no shape '", e.name,
        "' (the reference must be the exact matrix of the same dataset)");
  // A cache that cannot take files (a file in its place, a read-only folder) stops the run before any work.
  if (!options.cache_dir.empty() && comm.is_root()) check_output_directory(options.cache_dir);
  const std::filesystem::path cache_dir(options.cache_dir);
  const DiskCache cache(options.cache_dir.empty() ? "" : (cache_dir / "forms").string());
  CanonicalFormOptions co = options.canon;
  if (!co.progress) co.progress = polls_of(options.progress);  // the run's stop, in each form
  co.point_set = true;  // the pairs need no correspondence: a method from outside may give any point set
  const long computed_by_ranks = comm.size() > 1 ? canonize_share(data, cache, co, comm) : 0;
  std::vector<Points> forms;
  std::vector<std::string> keys;
  dataset_forms(data, cache, co, options, result, forms, keys);
  // The forms the ranks computed were read from the cache here: count them as computed.
  result.forms_computed += computed_by_ranks;
  result.forms_cached -= computed_by_ranks;
  CSHAPES_REQUIRE(forms.size() >= 2, options.data, ": ", forms.size(), " usable shapes (",
                  result.skipped.size(), " skipped), a distance matrix needs at least 2");
  result.profile.push_back(stage_time("forms", co.method, watch));
  watch.restart();
  PairwiseDistanceOptions po = options.pairs;
  po.cache_dir = options.cache_dir.empty() ? "" : (cache_dir / "pairs").string();
  po.progress = renamed_stage(options.progress, "distances, " + canonical_form_method_title(co.method));
  po.communicator = &comm;

  // Two-stage: descriptors rank the candidates, ICP aligns only those pairs.
  Eigen::MatrixXd descriptor_distances;
  if (options.two_stage_k > 0) descriptor_distances = two_stage_candidates(forms, options, result, po);
  result.distances = pairwise_distances(forms, keys, po);
  if (options.two_stage_k > 0 && comm.is_root()) {
    PairwiseDistanceResult& d = result.distances;
    for (Eigen::MatrixXd* M : {&d.hausdorff, &d.chamfer, &d.rmse})
      rank_unmeasured_last(*M, descriptor_distances);
    if (!options.reference.empty()) result.two_stage.recall = reference_recall(reference, options, result);
  }
  result.profile.push_back(stage_time("pairs", co.method, watch));
  return result;
}

std::map<std::string, long> precompute_shared_geodesic_forms(const DatasetDistanceOptions& options,
                                                             const std::vector<std::string>& methods,
                                                             std::vector<StageTime>* profile) {
  std::map<std::string, long> computed;
  const Communicator& comm = options.communicator ? *options.communicator : single_process();
  std::vector<CanonicalFormOptions> shared;
  std::string joined;
  for (const std::string& method : methods) {
    const CanonicalFormMethod* m = find_canonical_form_method(method);
    if (!m || !m->uses_geodesic_matrix) continue;
    CanonicalFormOptions co = options.canon;
    co.method = method;
    co.point_set = true;  // as dataset_distances sets it: the same cache keys
    co.note = {};
    co.progress = polls_of(options.progress);
    shared.push_back(co);
    joined += (joined.empty() ? "" : "+") + method;
  }
  if (shared.size() < 2 || options.cache_dir.empty() || comm.size() > 1) return computed;
  const Stopwatch watch;
  const Dataset data = read_dataset(options.data, options.allow_outside);
  const DiskCache cache((std::filesystem::path(options.cache_dir) / "forms").string());
  for (size_t i = 0; i < data.entries.size(); ++i) {
    const DatasetEntry& e = data.entries[i];
    if (options.progress)
      options.progress("canonical forms, " + joined, static_cast<double>(i),
                       static_cast<double>(data.entries.size()));
    Mesh mesh;
    try {
      mesh = read_mesh(e.path);
    } catch (const Error&) {
      continue;  // the method's pass says why
    }
    for (CanonicalFormOptions& co : shared) co.name = e.path;
    // Landmark MDS (a large mesh) computes no full matrix: nothing to share, the methods' passes do it.
    if (mds_uses_landmarks(shared.front(), mesh.num_vertices())) continue;
    try {
      const std::vector<CachedForm> forms = cached_canonical_forms(cache, mesh, shared);
      for (size_t k = 0; k < forms.size(); ++k)
        if (!forms[k].cached) ++computed[shared[k].method];
    } catch (const WriteError&) {
      throw;  // the cache cannot be written: every later stage would fail too
    } catch (const Error&) {
      // the method's pass meets the same error and reports it (or stops, under strict)
    }
  }
  if (profile) profile->push_back(stage_time("forms", joined, watch));
  return computed;
}

}  // namespace cshapes
