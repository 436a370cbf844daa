#include "cshapes/pipeline/canonical_forms.h"

#include "cshapes/pipeline/form_quality_json.h"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <new>
#include <nlohmann/json.hpp>
#include <optional>
#include <typeinfo>

#include "cshapes/canon/smacof.h"
#include "cshapes/mesh/unit_scale.h"
#include "cshapes/pipeline/canonical_form_methods.h"
#include "cshapes/pipeline/form_quality_json.h"
#include "cshapes/support/error.h"
#include "cshapes/support/threads.h"
#include "cshapes/support/timing.h"

namespace cshapes {

Edges constraint_edges(const Mesh& mesh, const KnnGraphOptions& knn) {
  return mesh.is_point_cloud() ? knn_graph(mesh.V, knn) : mesh_edges(mesh.F);
}

FormQuality canonical_form_quality(const Mesh& mesh, const CanonicalFormOptions& options,
                                   const CanonicalForm& form) {
  const Edges E = constraint_edges(mesh, options.knn);
  const std::vector<bool> torn = torn_edge_flags(E, form.torn_edges);
  FormQuality quality = form_quality(mesh.V, E, form.X, form.torn_edges.rows() ? &torn : nullptr);
  if (!form.breakdown.empty()) fail_form_quality(quality, form.breakdown);
  return quality;
}

nlohmann::json form_summary_json(const CanonicalForm& form) {
  nlohmann::json summary = form.details.is_object() ? form.details : nlohmann::json::object();
  if (form.quality) summary["form_quality"] = form_quality_json(*form.quality);
  return summary;
}

namespace {

std::function<void(GeodesicMethod, const std::string&)>& geodesics_test_hook() {
  static std::function<void(GeodesicMethod, const std::string&)> hook;
  return hook;
}

// The methods a failing geodesic method falls back to, in order: the heat methods to fast marching.
std::optional<GeodesicMethod> geodesic_fallback_method(GeodesicMethod method) {
  if (method == GeodesicMethod::Heat || method == GeodesicMethod::HeatCgal)
    return GeodesicMethod::FastMarching;
  return std::nullopt;
}

// compute(method) by options.geodesics.method; a method that fails on this mesh (a cshapes::Error, not the
// run's own I/O) falls back to the next one (heat → fast marching) unless options.strict; *fallback then
// says which failed and why.
template <class Compute>
auto with_geodesic_fallback(const CanonicalFormOptions& options, std::string* fallback, Compute&& compute) {
  // The run's own files and I/O failing are never the method's failure on this mesh.
  auto the_runs_own = [](const Error& e) {
    return dynamic_cast<const IoError*>(&e) != nullptr || dynamic_cast<const FileError*>(&e) != nullptr;
  };
  try {
    return compute(options.geodesics.method);
  } catch (const Error& error) {
    const std::optional<GeodesicMethod> next = geodesic_fallback_method(options.geodesics.method);
    if (the_runs_own(error) || options.strict || !next) throw;
    const std::string text = to_string(options.geodesics.method) + " geodesics failed (" + error.what() +
                             "); " + to_string(*next) + " instead";
    say(options.note, options.name + ": " + text);
    if (fallback) *fallback = text;
    try {
      return compute(*next);
    } catch (const Error& next_error) {
      if (the_runs_own(next_error)) throw;
      // Both failed: say so, the first method's reason included.
      fail(to_string(options.geodesics.method), " geodesics failed (", error.what(), "), and so did ",
           to_string(*next), " (", next_error.what(), ")");
    }
  }
}

// All pairs on a surface, with the fallback above.
DistanceMatrix surface_geodesics(const Mesh& mesh, const CanonicalFormOptions& options,
                                 std::string* fallback) {
  GeodesicOptions go = options.geodesics;
  if (!go.progress) go.progress = options.progress;
  return with_geodesic_fallback(options, fallback, [&](GeodesicMethod method) {
    go.method = method;
    if (geodesics_test_hook()) geodesics_test_hook()(go.method, options.name);
    return all_pairs_geodesics(mesh, go);
  });
}

}  // namespace

DistanceMatrix canonical_form_geodesics(const Mesh& mesh, const CanonicalFormOptions& options,
                                        std::string* fallback) {
  if (!mesh.is_point_cloud()) return surface_geodesics(mesh, options, fallback);
  // A point cloud has no surface: graph distances on its kNN graph (as Isomap does).
  Edges E = knn_graph(mesh.V, options.knn);
  Components comp = connected_components(mesh.num_vertices(), E);
  CSHAPES_REQUIRE(comp.count == 1, "point cloud: its ", options.knn.k, "-nearest-neighbour graph has ",
                  comp.count, " components; MDS needs one (raise --knn)");
  const Index n = mesh.num_vertices();
  require_memory(distance_matrix_bytes(n), "all-pairs graph distances on " + std::to_string(n) + " points");
  DistanceMatrix D = uninitialized_distance_matrix(n, n);
  Adjacency adj = adjacency(n, E);
  Eigen::VectorXd w = edge_lengths(mesh.V, E);
#pragma omp parallel for schedule(dynamic, 16)
  for (Index s = 0; s < n; ++s) D.col(s) = dijkstra(n, adj, w, {static_cast<int>(s)}).cast<float>();
  symmetrize_distances(D);
  return D;
}

namespace {

// The L × n float rows of landmark MDS, checked before any work as the full matrix is.
void require_landmark_memory(const Mesh& mesh, const CanonicalFormOptions& options) {
  const Index n = mesh.num_vertices(), count = std::min<Index>(options.mds_solver.landmarks, n);
  require_memory(4.0 * static_cast<double>(count) * static_cast<double>(n),
                 detail::concat(options.name, ": ", options.method, "'s ", count,
                                " landmark geodesic rows on ", n, " vertices"));
}

}  // namespace

LandmarkGeodesics canonical_form_landmark_geodesics(const Mesh& mesh, const CanonicalFormOptions& options,
                                                    std::string* fallback) {
  const Index count = std::min<Index>(options.mds_solver.landmarks, mesh.num_vertices());
  require_landmark_memory(mesh, options);
  if (mesh.is_point_cloud()) {
    const SingleSourceGeodesics graph(mesh.V, knn_graph(mesh.V, options.knn));
    return landmark_geodesics(graph, mesh.V, count, -1, options.progress);
  }
  LandmarkGeodesicsOptions lo;
  lo.count = count;
  lo.geodesics = options.geodesics;
  if (!lo.geodesics.progress) lo.geodesics.progress = options.progress;
  return with_geodesic_fallback(options, fallback, [&](GeodesicMethod method) {
    lo.geodesics.method = method;
    if (geodesics_test_hook()) geodesics_test_hook()(method, options.name);
    return landmark_geodesics(mesh, lo);
  });
}

double canonical_form_scale(const Mesh& mesh) {
  const double scale = power_of_two_unit_scale(mesh.V);
  return scale >= kCanonicalFormLowestScale && scale <= kCanonicalFormHighestScale ? 1 : scale;
}

bool mds_uses_landmarks(const CanonicalFormOptions& options, Index n) {
  return options.distances_file.empty() &&
         mds_uses_landmarks(options.mds_solver, n, available_memory_bytes());
}

namespace {

// A CanonicalForm as a cache value (data/cache.h stores it as CBOR: compact and exact for doubles).
nlohmann::json to_json(const CanonicalForm& f) {
  nlohmann::json j;
  j["n"] = f.X.rows();
  j["X"] = std::vector<double>(f.X.data(), f.X.data() + f.X.size());
  j["torn"] = std::vector<double>(f.torn.data(), f.torn.data() + f.torn.size());
  j["precompute_seconds"] = f.precompute_seconds;
  j["solve_seconds"] = f.solve_seconds;
  j["iterations"] = f.iterations;
  j["seconds_per_iteration"] = f.seconds_per_iteration;
  j["history_columns"] = f.history_columns;
  j["history_rows"] = f.history_rows;
  j["summary"] = form_summary_json(f).dump();
  j["valid"] = std::vector<double>(f.valid.data(), f.valid.data() + f.valid.size());
  if (!f.geodesics_fallback.empty()) j["geodesics_fallback"] = f.geodesics_fallback;
  return j;
}

CanonicalForm form_from_json(const nlohmann::json& j) {
  CanonicalForm f;
  const Index n = j["n"].get<Index>();
  std::vector<double> X = j["X"].get<std::vector<double>>(), torn = j["torn"].get<std::vector<double>>();
  CSHAPES_REQUIRE(static_cast<Index>(X.size()) == 3 * n, "cache entry: inconsistent canonical form");
  f.X = Eigen::Map<const Points>(X.data(), n, 3);
  f.torn = Eigen::Map<const Eigen::VectorXd>(torn.data(), static_cast<Index>(torn.size()));
  f.precompute_seconds = j["precompute_seconds"];
  f.solve_seconds = j["solve_seconds"];
  f.iterations = j["iterations"];
  f.seconds_per_iteration = j["seconds_per_iteration"];
  f.history_columns = j["history_columns"].get<std::vector<std::string>>();
  f.history_rows = j["history_rows"].get<std::vector<std::vector<double>>>();
  nlohmann::json summary = nlohmann::json::parse(j["summary"].get<std::string>());
  if (summary.contains("form_quality")) {
    f.quality = form_quality_from_json(summary["form_quality"]);
    summary.erase("form_quality");
  }
  f.details = std::move(summary);
  // Entries written before repairs existed are of meshes that needed none: every vertex valid.
  std::vector<double> valid =
      j.contains("valid") ? j["valid"].get<std::vector<double>>() : std::vector<double>();
  CSHAPES_REQUIRE(valid.empty() || static_cast<Index>(valid.size()) == n,
                  "cache entry: inconsistent valid flags");
  f.valid = valid.empty() ? Eigen::VectorXd::Ones(n)
                          : Eigen::VectorXd(Eigen::Map<const Eigen::VectorXd>(valid.data(), n));
  f.geodesics_fallback = j.value("geodesics_fallback", std::string());
  return f;
}

}  // namespace

RepairedMesh repair_for_canonical_form(const Mesh& mesh, const CanonicalFormOptions& options) {
  RepairOptions ro;
  ro.strict = options.strict;
  ro.name = options.name;
  ro.progress = polls_of(options.progress);
  const CanonicalFormMethod& method = canonical_form_method(options.method);
  if (method.takes_mesh_as_given) {  // an outside method: the mesh as the experiment has it
    RepairedMesh as_given;
    as_given.mesh = mesh;
    as_given.input_vertices = mesh.num_vertices();
    as_given.vertex_map.resize(mesh.num_vertices());
    for (Index i = 0; i < mesh.num_vertices(); ++i) as_given.vertex_map[i] = static_cast<int>(i);
    return as_given;
  }
  ro.purpose = method.repair_purpose;
  return repair_for(mesh, method.requirements, ro);
}

DistanceMatrix distances_on_repaired_mesh(const DistanceMatrix& D, const RepairedMesh& repaired,
                                          const std::string& source) {
  const Index n = repaired.mesh.num_vertices();
  // The input's size first: `cshapes geodesics` writes that on a repaired mesh, and a repair that drops some
  // vertices and splits others can leave the count unchanged while the order is not.
  if (D.rows() == repaired.input_vertices && D.cols() == D.rows()) {
    if (!repaired.changed()) return D;
  } else {
    CSHAPES_REQUIRE(D.rows() == n && D.cols() == n, source, ": has ", D.rows(), " points but the mesh has ",
                    repaired.input_vertices, " vertices (", n, " after repair)");
    return D;
  }
  // The input was repaired (vertices dropped or split): the rows and columns of the vertices it maps to.
  require_memory(distance_matrix_bytes(n), "restricting " + source + " to the repaired mesh");
  DistanceMatrix sub = uninitialized_distance_matrix(n, n);
  for (Index j = 0; j < n; ++j)
    for (Index i = 0; i < n; ++i) sub(i, j) = D(repaired.vertex_map[i], repaired.vertex_map[j]);
  return sub;
}

void set_geodesics_test_hook(std::function<void(GeodesicMethod, const std::string&)> hook) {
  geodesics_test_hook() = std::move(hook);
}

namespace {

// A distance matrix read from a file, as every method that embeds one requires it (cmds accepted an
// asymmetric matrix and a non-zero diagonal that SMACOF refused): square, n ≥ 4, finite and non-negative,
// symmetric to float rounding (validate_distance_matrix), and a diagonal of zeros to the same rounding.
void require_distance_matrix(const DistanceMatrix& D, const std::string& what) {
  validate_distance_matrix(D, what);
  const float largest = D.maxCoeff();
  for (Index i = 0; i < D.rows(); ++i)
    CSHAPES_REQUIRE(std::abs(D(i, i)) <= 1e-5f * largest, what, ": distance (", i, ", ", i, ") is ", D(i, i),
                    "; a point's distance to itself must be 0");
}

// Distances of a mesh, in the units of its copy scaled by `scale` (a power of two: exact unless the result
// leaves float's range, which a matrix consistent with its mesh does not).
void scale_distances(DistanceMatrix& D, double scale) {
  for (Index j = 0; j < D.cols(); ++j)
    for (Index i = 0; i < D.rows(); ++i) D(i, j) = static_cast<float>(static_cast<double>(D(i, j)) * scale);
}

CanonicalForm canonical_form_of(const Mesh& mesh, const CanonicalFormOptions& options,
                                const DistanceMatrix* D, double D_seconds, const std::string& D_fallback) {
  // Points all in one place have no shape to canonize (every method would return them as they are, "ok").
  CSHAPES_REQUIRE(
      mesh.num_vertices() == 0 || (mesh.V.colwise().maxCoeff() - mesh.V.colwise().minCoeff()).maxCoeff() > 0,
      options.name, ": all ", mesh.num_vertices(),
      " points coincide (a degenerate point set): nothing to canonize");
  const CanonicalFormMethod& method = canonical_form_method(options.method);
  // The n×n matrix of the methods that embed it is checked against the memory before anything else is done.
  // So are landmark MDS's L rows.
  if (method.uses_geodesic_matrix && !D) {
    if (!mds_uses_landmarks(options, mesh.num_vertices()))
      require_memory(distance_matrix_bytes(mesh.num_vertices()),
                     detail::concat(options.name, ": ", options.method, "'s all-pairs distances on ",
                                    mesh.num_vertices(), " vertices"));
    else
      require_landmark_memory(mesh, options);
  }
  if (method.memory_bytes)
    require_memory(
        method.memory_bytes(mesh.num_vertices(), options),
        detail::concat(options.name, ": ", options.method, " on ", mesh.num_vertices(), " vertices"));
  const RepairedMesh repaired = repair_for_canonical_form(mesh, options);
  // Far from unit size, the repaired mesh (a dropped stray vertex no longer sets the size) on a copy scaled
  // by a power of two (exact), and the form scaled back.
  const double scale = method.takes_mesh_as_given ? 1.0 : canonical_form_scale(repaired.mesh);
  const Mesh scaled = scale == 1 ? Mesh{} : Mesh{repaired.mesh.V * scale, repaired.mesh.F};
  DistanceMatrix owned;  // read from distances_file, or the given D at unit size
  if (method.uses_geodesic_matrix && !D && !options.distances_file.empty()) {
    const auto start = WallClock::now();
    owned = distances_on_repaired_mesh(read_distance_matrix(options.distances_file), repaired,
                                       options.distances_file);
    require_distance_matrix(owned, options.distances_file);
    if (scale != 1) scale_distances(owned, scale);
    D = &owned;
    D_seconds = seconds_since(start);
  } else if (D && scale != 1) {
    require_memory(distance_matrix_bytes(D->rows()), options.name + ": the distance matrix at unit size");
    owned = *D;
    scale_distances(owned, scale);
    D = &owned;
  }
  const Mesh& computed_on = scale == 1 ? repaired.mesh : scaled;
  CanonicalForm form =
      method.compute(computed_on, options, GivenDistances{D, D_seconds, D ? D_fallback : ""});
  // Every method's form checked the same way, here (on the mesh it was computed on: the check is scale-free).
  // A point set from outside (options.point_set) has no rows per vertex: nothing to measure or map back.
  const bool point_set = method.takes_mesh_as_given && form.X.rows() != computed_on.num_vertices();
  if (point_set) {
    FormQuality quality;
    quality.description = "not measured: a point set of " + std::to_string(form.X.rows()) +
                          " points, not one per vertex (its edges are unknown)";
    form.quality = quality;
    form.valid = Eigen::VectorXd::Ones(form.X.rows());
    say(options.note, options.method + ": form quality " + form.quality->description);
    return form;
  }
  form.quality = canonical_form_quality(computed_on, options, form);
  say(options.note, options.method + ": form quality " + form.quality->description);
  if (scale != 1) {
    form.X /= scale;  // a power of two: exact
    form.details["computed_at_scale"] = scale;
    say(options.note,
        options.name + ": computed on a copy scaled by " + std::to_string(scale) +
            " (its size was far from 1); the form is scaled back, while its summary's energies, "
            "steps and stresses are the copy's");
  }
  // Back to the input's vertices (a copy when nothing was repaired).
  const Index n = mesh.num_vertices();
  form.X = to_input_vertices(form.X, repaired.vertex_map, n);
  if (form.torn.size()) form.torn = to_input_vertices(form.torn, repaired.vertex_map, n, 0.0);
  form.valid = valid_input_vertices(repaired.vertex_map, n);
  form.repairs = repaired.actions;
  form.repair_text = repaired.text;
  return form;
}

}  // namespace

CanonicalForm canonical_form(const Mesh& mesh, const CanonicalFormOptions& options, const DistanceMatrix* D,
                             double D_seconds, const std::string& D_fallback) {
  refresh_threads();  // each form with the cores free now (support/threads.h); forms do not depend on the
                      // count
  try {
    return canonical_form_of(mesh, options, D, D_seconds, D_fallback);
  } catch (const Error& error) {
    // Every error names the mesh it is about ("non-finite Coulomb gradient" alone does not): a plain Error
    // whose message does not start with the name gets it in front; other types pass unchanged.
    const std::string message = error.what();
    if (typeid(error) != typeid(Error) || message.rfind(options.name, 0) == 0) throw;
    throw Error(options.name + ": " + message);
  } catch (const std::bad_alloc&) {
    throw;
  } catch (const std::exception& error) {
    // A library's own exception (Spectra's "TridiagEigen: eigen decomposition failed" on an extreme mesh)
    // is this shape's failure, named, as cshapes::Error: the drivers leave the shape out and go on, where it
    // ended the whole run with exit 1.
    throw Error(options.name + ": " + options.method + ": " + error.what());
  }
}

std::string canonical_form_key(const CanonicalFormOptions& options) {
  const CanonicalFormMethod& method = canonical_form_method(options.method);
  std::string key =
      options_key(options, [&method](const char* field) { return method_reads_field(method, field); });
  // The version of the method's arithmetic, from 2 on (at 1 the key is the one from before versions).
  if (method.results_version > 1) key += ";results-v" + std::to_string(method.results_version);
  // An outside method: its door and what identifies its code (pipeline/outside_methods.h).
  if (!method.door.empty()) key += ";door=" + method.door + ";" + method.key_text;
  return key;
}

std::string mesh_content_key(const Mesh& mesh) {
  std::string bytes;
  auto append = [&bytes](const void* data, size_t size) {
    bytes.append(static_cast<const char*>(data), size);
  };
  Index n = mesh.num_vertices(), m = mesh.num_faces();
  append(&n, sizeof n);
  append(&m, sizeof m);
  append(mesh.V.data(), sizeof(double) * mesh.V.size());
  append(mesh.F.data(), sizeof(int) * mesh.F.size());
  return sha256_hex(bytes);
}

std::string canonical_form_cache_key(const Mesh& mesh, const CanonicalFormOptions& options) {
  // Built from the options' field lists (support/option_fields.h): every field by value, SMACOF's vertex
  // weights included. The tag's version changes with what the key covers, so entries under an older key are
  // not found and their forms are computed again, once (the versions: docs/design.md, "Caches").
  return cache_key({"canonical-form-v2", mesh_content_key(mesh), canonical_form_key(options)});
}

CanonicalForm cached_canonical_form(const DiskCache& cache, const Mesh& mesh,
                                    const CanonicalFormOptions& options, bool* was_cached,
                                    const DistanceMatrix* D, double D_seconds,
                                    const std::string& D_fallback) {
  const std::string key = canonical_form_cache_key(mesh, options);
  if (!canonical_form_method(options.method).cacheable) {  // forms read from a folder: read again
    if (was_cached) *was_cached = false;
    return canonical_form(mesh, options, D, D_seconds, D_fallback);
  }
  if (std::optional<nlohmann::json> hit = cache.get_json(key)) {
    // The repair (cheap) is redone for its report under this call's name, and so that --strict refuses.
    const RepairedMesh repaired = repair_for_canonical_form(mesh, options);
    if (was_cached) *was_cached = true;
    CanonicalForm form = form_from_json(*hit);
    CSHAPES_REQUIRE(options.point_set || form.X.rows() == mesh.num_vertices(), options.name, ": method ",
                    options.method, ": the cached form is a point set of ", form.X.rows(),
                    " points, not one row per vertex (", mesh.num_vertices(),
                    "): it was given where any point set does (retrieval); this experiment needs one row per "
                    "vertex, in the mesh's order");
    form.repairs = repaired.actions;
    form.repair_text = repaired.text;
    return form;
  }
  if (was_cached) *was_cached = false;
  CanonicalForm form = canonical_form(mesh, options, D, D_seconds, D_fallback);
  cache.put_json(key, to_json(form));
  return form;
}

std::vector<CanonicalFormOptions> options_per_method(const CanonicalFormOptions& base,
                                                     const std::vector<std::string>& methods,
                                                     const std::string& name) {
  std::vector<CanonicalFormOptions> out;
  for (const std::string& m : methods) {
    CanonicalFormOptions co = base;
    co.method = m;
    co.name = name;
    co.progress = polls_of(base.progress);  // the caller's stop, not per-form reports
    co.note = {};
    out.push_back(std::move(co));
  }
  return out;
}

std::vector<CachedForm> cached_canonical_forms(const DiskCache& cache, const Mesh& mesh,
                                               const std::vector<CanonicalFormOptions>& options, size_t* at) {
  std::vector<CachedForm> result(options.size());
  // The shared matrix and the options it was computed for (heat/FMM settings and the repair).
  DistanceMatrix D;
  const CanonicalFormOptions* D_for = nullptr;
  double D_seconds = 0;
  std::string D_fallback;  // the geodesic method that failed for D, and why; "" when none did
  auto same_geodesics = [](const CanonicalFormOptions& a, const CanonicalFormOptions& b) {
    return a.geodesics.method == b.geodesics.method && a.geodesics.heat_mode == b.geodesics.heat_mode &&
           a.geodesics.heat_time_factor == b.geodesics.heat_time_factor && a.strict == b.strict &&
           a.knn.k == b.knn.k;
  };
  for (size_t k = 0; k < options.size(); ++k) {
    const CanonicalFormOptions& co = options[k];
    CachedForm& out = result[k];
    if (at) *at = k;
    const auto start = WallClock::now();
    out.key = canonical_form_cache_key(mesh, co);
    const bool mds = canonical_form_method(co.method).uses_geodesic_matrix && co.distances_file.empty() &&
                     !mds_uses_landmarks(co, mesh.num_vertices());
    if (mds && !(D_for && same_geodesics(*D_for, co)) &&
        !std::filesystem::exists(cache.entry_path(out.key))) {
      D_fallback.clear();
      const Mesh repaired = repair_for_canonical_form(mesh, co).mesh;
      // A shared matrix only at the mesh's own size: a form far from unit size computes its geodesics on
      // its scaled copy (float32 distances would leave their range here).
      D_for = nullptr;
      if (canonical_form_scale(repaired) == 1) {
        D = canonical_form_geodesics(repaired, co, &D_fallback);
        D_seconds = seconds_since(start);
        D_for = &co;
      }
    }
    const bool use_D = mds && D_for && same_geodesics(*D_for, co);
    out.form = cached_canonical_form(cache, mesh, co, &out.cached, use_D ? &D : nullptr, D_seconds,
                                     use_D ? D_fallback : std::string());
    out.seconds = seconds_since(start);
  }
  return result;
}

}  // namespace cshapes
