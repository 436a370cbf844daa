#include "pipeline/canonical_forms.h"

#include <cmath>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <optional>
#include <sstream>
#include <typeinfo>

#include "core/error.h"
#include "core/heat_method.h"
#include "core/timing.h"
#include "pipeline/form_quality_json.h"

namespace cshapes {

namespace {

// The edges standing in for the mesh's: its triangle edges, or a kNN graph for a point cloud.
Edges constraint_edges(const Mesh& mesh, const KnnGraphOptions& knn) {
  return mesh.is_point_cloud() ? knn_graph(mesh.V, knn) : mesh_edges(mesh.F);
}

std::function<void(GeodesicMethod, const std::string&)>& geodesics_test_hook() {
  static std::function<void(GeodesicMethod, const std::string&)> hook;
  return hook;
}

void say(const CanonicalFormOptions& options, const std::string& line) {
  if (options.note) options.note(line);
}

// The methods a failing geodesic method falls back to, in order: the heat methods to fast marching.
std::optional<GeodesicMethod> geodesic_fallback_method(GeodesicMethod method) {
  if (method == GeodesicMethod::Heat || method == GeodesicMethod::HeatCgal)
    return GeodesicMethod::FastMarching;
  return std::nullopt;
}

// All pairs on a surface. A method that fails on this mesh (a cshapes::Error, not the run's own I/O) falls
// back to the next one (heat → fast marching) unless options.strict; *fallback then says which failed and
// why.
DistanceMatrix surface_geodesics(const Mesh& mesh, const CanonicalFormOptions& options,
                                 std::string* fallback) {
  GeodesicOptions go = options.geodesics;
  if (!go.progress) go.progress = options.progress;
  try {
    if (geodesics_test_hook()) geodesics_test_hook()(go.method, options.name);
    return all_pairs_geodesics(mesh, go);
  } catch (const IoError&) {
    throw;
  } catch (const FileError&) {
    throw;
  } catch (const Error& error) {
    const std::optional<GeodesicMethod> next = geodesic_fallback_method(go.method);
    if (options.strict || !next) throw;
    const std::string text =
        to_string(go.method) + " geodesics failed (" + error.what() + "); " + to_string(*next) + " instead";
    say(options, options.name + ": " + text);
    if (fallback) *fallback = text;
    go.method = *next;
    try {
      if (geodesics_test_hook()) geodesics_test_hook()(go.method, options.name);
      return all_pairs_geodesics(mesh, go);
    } catch (const IoError&) {
      throw;
    } catch (const FileError&) {
      throw;
    } catch (const Error& next_error) {
      // Both failed: say so, the first method's reason included.
      fail(to_string(options.geodesics.method), " geodesics failed (", error.what(), "), and so did ",
           to_string(*next), " (", next_error.what(), ")");
    }
  }
}

DistanceMatrix geodesic_matrix(const Mesh& mesh, const CanonicalFormOptions& options,
                               std::string* fallback = nullptr) {
  if (!mesh.is_point_cloud()) return surface_geodesics(mesh, options, fallback);
  // A point cloud has no surface: graph distances on its kNN graph (as Isomap does).
  Edges E = knn_graph(mesh.V, options.knn);
  Components comp = connected_components(mesh.num_vertices(), E);
  CSHAPES_REQUIRE(comp.count == 1, "point cloud: its ", options.knn.k, "-nearest-neighbour graph has ",
                  comp.count, " components; MDS needs one (raise k)");
  const Index n = mesh.num_vertices();
  require_memory(distance_matrix_bytes(n), "all-pairs graph distances on " + std::to_string(n) + " points");
  DistanceMatrix D(n, n);
  Adjacency adj = adjacency(n, E);
  Eigen::VectorXd w = edge_lengths(mesh.V, E);
#pragma omp parallel for schedule(dynamic, 16)
  for (Index s = 0; s < n; ++s) D.col(s) = dijkstra(n, adj, w, {static_cast<int>(s)}).cast<float>();
  symmetrize_distances(D);
  return D;
}

CanonicalForm coulomb_form(const Mesh& mesh, const CanonicalFormOptions& options) {
  auto start = WallClock::now();
  const Edges E = constraint_edges(mesh, options.knn);
  if (mesh.is_point_cloud()) {
    // A point cloud's kNN graph stands in for the mesh's edges; its parts would drift apart if it fell apart.
    const Components components = connected_components(mesh.num_vertices(), E);
    CSHAPES_REQUIRE(components.count == 1, options.name, ": the ", options.knn.k,
                    "-nearest-neighbour graph has ", components.count,
                    " components; its parts would drift apart: raise --knn");
    say(options, options.name + ": point cloud, " + std::to_string(E.rows()) +
                     " kNN edges (k = " + std::to_string(options.knn.k) + ")");
  }
  CanonicalForm form;
  form.precompute_seconds = seconds_since(start);
  CoulombCanonOptions co = options.coulomb;
  if (!co.progress) co.progress = options.progress;
  CoulombCanonResult r = coulomb_canonical_form(mesh.V, E, co);
  form.X = r.X;
  form.torn = r.torn_vertices;
  form.iterations = r.iterations;
  form.solve_seconds = r.seconds;
  form.seconds_per_iteration = r.iterations ? r.seconds / r.iterations : 0;
  form.history_columns = {"iteration", "energy",     "mean_violation", "max_violation", "step",
                          "max_move",  "torn_edges", "shape_change",   "momentum",      "seconds"};
  for (const CoulombIterationRecord& h : r.history)
    form.history_rows.push_back({double(h.iteration), h.energy, h.mean_violation, h.max_violation, h.step,
                                 h.max_move, double(h.torn_edges), h.shape_change, h.momentum, h.seconds});
  form.summary_json = nlohmann::json{{"vertices", mesh.num_vertices()},
                                     {"edges", E.rows()},
                                     {"torn_edges", r.torn_edges.rows()},
                                     {"iterations", r.iterations},
                                     {"converged", r.converged},
                                     {"stop_reason", r.stop_reason},
                                     {"energy", r.energy},
                                     {"mean_violation", r.violation.mean_relative},
                                     {"max_violation", r.violation.max_relative},
                                     {"median_length_ratio", r.violation.median_length_ratio},
                                     {"seconds", r.seconds},
                                     {"scheme", to_string(co.scheme)},
                                     {"step_rule", to_string(co.step_rule)},
                                     {"step_gradient", to_string(co.step_gradient)},
                                     {"projection", to_string(co.projection.norm)},
                                     {"projection_steps", co.projection.steps},
                                     {"form_quality", form_quality_json(r.quality)}}
                          .dump();
  say(options, "coulomb: " + std::to_string(r.iterations) + " iterations (" + r.stop_reason + ") in " +
                   std::to_string(r.seconds) + " s; mean violation " +
                   std::to_string(r.violation.mean_relative) + ", " + std::to_string(r.torn_edges.rows()) +
                   " edges torn");
  say(options, "coulomb: form quality " + r.quality.description);
  return form;
}

nlohmann::json cmds_summary(const ClassicalMdsResult& r) {
  return {{"eigenvalues", {r.eigenvalues[0], r.eigenvalues[1], r.eigenvalues[2]}},
          {"most_negative_eigenvalue", std::isfinite(r.most_negative_eigenvalue)
                                           ? nlohmann::json(r.most_negative_eigenvalue)
                                           : nlohmann::json(nullptr)},
          {"trace", r.trace},
          {"frobenius_squared", r.frobenius_squared},
          {"explained_energy", r.explained_energy},
          {"negative_mass_lower_bound", r.negative_mass_lower_bound},
          {"negative_energy_upper_bound", r.negative_energy_upper_bound},
          {"matrix_products", r.matrix_products},
          {"seconds", r.seconds}};
}

// SMACOF's result as a form's X, iterations and history.
void set_smacof_result(CanonicalForm& form, const SmacofResult& sr) {
  form.X = sr.X;
  form.iterations = sr.iterations;
  form.seconds_per_iteration = sr.seconds_per_iteration;
  form.history_columns = {"iteration", "passes", "normalized_stress", "extrapolated"};
  form.history_rows.clear();
  for (size_t k = 0; k < sr.stress_history.size(); ++k)
    form.history_rows.push_back({static_cast<double>(k), static_cast<double>(sr.passes_history[k]),
                                 sr.stress_history[k], sr.extrapolated_history[k] ? 1.0 : 0.0});
}

nlohmann::json smacof_summary(const SmacofResult& sr, const SmacofOptions& so) {
  return {{"normalized_stress", sr.normalized_stress},
          {"initial_normalized_stress",
           sr.stress_history.empty() ? sr.normalized_stress : sr.stress_history.front()},
          {"iterations", sr.iterations},
          {"stop_reason", sr.stop_reason},
          {"acceleration", to_string(so.acceleration)},
          {"extrapolations_accepted", sr.extrapolations_accepted},
          {"extrapolations_rejected", sr.extrapolations_rejected},
          {"seconds", sr.seconds},
          {"seconds_per_iteration", sr.seconds_per_iteration}};
}

ClassicalMdsResult run_classical_mds(const DistanceMatrix& D, const CanonicalFormOptions& options) {
  ClassicalMdsResult r = classical_mds(D, options.cmds);
  say(options, "classical MDS: eigenvalues " + std::to_string(r.eigenvalues[0]) + ", " +
                   std::to_string(r.eigenvalues[1]) + ", " + std::to_string(r.eigenvalues[2]) +
                   "; 3-D keeps " + std::to_string(100 * r.explained_energy) +
                   "% of the spectrum's energy; most negative " + "eigenvalue " +
                   std::to_string(r.most_negative_eigenvalue) + " in " + std::to_string(r.seconds) + " s");
  return r;
}

CanonicalForm mds_form(const Mesh& mesh, const CanonicalFormOptions& options, const DistanceMatrix* given,
                       double given_seconds, const std::string& given_fallback) {
  CanonicalForm form;
  form.precompute_seconds = given_seconds;
  form.geodesics_fallback = given ? given_fallback : "";
  DistanceMatrix computed;
  if (!given) {
    auto start = WallClock::now();
    computed = geodesic_matrix(mesh, options, &form.geodesics_fallback);
    form.precompute_seconds = seconds_since(start);
    given = &computed;
  }
  CSHAPES_REQUIRE(given->rows() == mesh.num_vertices(), "MDS: distance matrix has ", given->rows(),
                  " rows for a mesh of ", mesh.num_vertices(), " vertices");
  auto start = WallClock::now();
  nlohmann::json summary = nlohmann::json::object();
  if (!form.geodesics_fallback.empty()) summary["geodesics_fallback"] = form.geodesics_fallback;
  if (form.geodesics_fallback.empty() && (options.geodesics.method == GeodesicMethod::Heat ||
                                          options.geodesics.method == GeodesicMethod::HeatCgal)) {
    const std::string warning = heat_method_warning(mesh);
    if (!warning.empty()) {
      summary["warning"] = warning;
      say(options, "warning: " + warning);
    }
  }
  const Edges E = constraint_edges(mesh, options.knn);
  Points X0;
  if (options.method == "cmds" || options.smacof_init == "cmds") {
    ClassicalMdsResult cm = run_classical_mds(*given, options);
    summary["classical_mds"] = cmds_summary(cm);
    X0 = std::move(cm.X);
  } else {
    CSHAPES_REQUIRE(options.smacof_init == "mesh", "smacof: unknown start '", options.smacof_init,
                    "'; known: cmds, mesh");
    X0 = mesh.V;
  }
  if (options.method == "cmds") {
    form.X = std::move(X0);
  } else {
    SmacofOptions so = options.smacof;
    if (!so.progress) so.progress = options.progress;
    CSHAPES_REQUIRE(options.smacof_weights == "uniform" || options.smacof_weights == "area",
                    "smacof: unknown weights '", options.smacof_weights, "'; known: uniform, area");
    if (options.smacof_weights == "area") so.vertex_weights = vertex_area_weights(mesh);
    SmacofResult sr = smacof(*given, X0, so);
    say(options, "SMACOF: normalised stress " + std::to_string(sr.stress_history.front()) + " -> " +
                     std::to_string(sr.normalized_stress) + " in " + std::to_string(sr.iterations) +
                     " iterations (" + sr.stop_reason + "), " + std::to_string(sr.seconds_per_iteration) +
                     " s per iteration");
    set_smacof_result(form, sr);
    summary["smacof"] = smacof_summary(sr, so);
    summary["smacof"]["init"] = options.smacof_init;
    summary["smacof"]["weights"] = options.smacof_weights;
  }
  form.solve_seconds = seconds_since(start);
  const FormQuality quality = form_quality(mesh.V, E, form.X);
  say(options, "form quality " + quality.description);
  summary["form_quality"] = form_quality_json(quality);
  form.summary_json = summary.dump();
  return form;
}

// A CanonicalForm as a cache value (eval/cache.h stores it as CBOR: compact and exact for doubles).
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
  j["summary"] = f.summary_json;
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
  f.summary_json = j["summary"].get<std::string>();
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

CanonicalForm classical_mds_form(const ClassicalMdsResult& r) {
  CanonicalForm form;
  form.X = r.X;
  form.valid = Eigen::VectorXd::Ones(r.X.rows());
  form.solve_seconds = r.seconds;
  form.summary_json = nlohmann::json{{"classical_mds", cmds_summary(r)}}.dump();
  return form;
}

CanonicalForm smacof_form(const SmacofResult& r, const SmacofOptions& options) {
  CanonicalForm form;
  set_smacof_result(form, r);
  form.valid = Eigen::VectorXd::Ones(r.X.rows());
  form.solve_seconds = r.seconds;
  form.summary_json = nlohmann::json{{"smacof", smacof_summary(r, options)}}.dump();
  return form;
}

const std::vector<std::string>& canonical_form_methods() {
  static const std::vector<std::string> methods = {"coulomb", "cmds", "smacof"};
  return methods;
}

MeshRequirements canonical_form_requirements(const std::string& method) {
  if (method == "coulomb") return MeshRequirements::edge_graph();
  if (method == "cmds" || method == "smacof") return MeshRequirements::manifold_surface();
  fail("unknown canonization method '", method, "'; known: coulomb, cmds, smacof");
}

RepairedMesh repair_for_canonical_form(const Mesh& mesh, const CanonicalFormOptions& options) {
  RepairOptions ro;
  ro.strict = options.strict;
  ro.name = options.name;
  ro.purpose = options.method == "coulomb"
                   ? "Coulomb canonization (the largest component's edge graph)"
                   : options.method + " (its geodesics need one manifold component without zero-area faces)";
  return repair_for(mesh, canonical_form_requirements(options.method), ro);
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
  DistanceMatrix sub(n, n);
  for (Index j = 0; j < n; ++j)
    for (Index i = 0; i < n; ++i) sub(i, j) = D(repaired.vertex_map[i], repaired.vertex_map[j]);
  return sub;
}

void set_geodesics_test_hook(std::function<void(GeodesicMethod, const std::string&)> hook) {
  geodesics_test_hook() = std::move(hook);
}

namespace {

CanonicalForm canonical_form_of(const Mesh& mesh, const CanonicalFormOptions& options, const DistanceMatrix* D,
                                double D_seconds, const std::string& D_fallback) {
  // Points all in one place have no shape to canonize (every method would return them as they are, "ok").
  CSHAPES_REQUIRE(
      mesh.num_vertices() == 0 || (mesh.V.colwise().maxCoeff() - mesh.V.colwise().minCoeff()).maxCoeff() > 0,
      options.name, ": all ", mesh.num_vertices(),
      " points coincide (a degenerate point set): nothing to canonize");
  // The n×n matrix of the MDS methods is checked against the memory before anything else is done.
  if (options.method != "coulomb" && !D)
    require_memory(distance_matrix_bytes(mesh.num_vertices()),
                   detail::concat(options.name, ": ", options.method, "'s all-pairs distances on ",
                                  mesh.num_vertices(), " vertices"));
  const RepairedMesh repaired = repair_for_canonical_form(mesh, options);
  DistanceMatrix from_file;
  if (options.method != "coulomb" && !D && !options.distances_file.empty()) {
    const auto start = WallClock::now();
    from_file = distances_on_repaired_mesh(read_distance_matrix(options.distances_file), repaired,
                                           options.distances_file);
    D = &from_file;
    D_seconds = seconds_since(start);
  }
  CanonicalForm form = options.method == "coulomb"
                           ? coulomb_form(repaired.mesh, options)
                           : mds_form(repaired.mesh, options, D, D_seconds, D_fallback);
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
  try {
    return canonical_form_of(mesh, options, D, D_seconds, D_fallback);
  } catch (const Error& error) {
    // Every error names the mesh it is about ("non-finite Coulomb gradient" alone does not): a plain Error
    // whose message does not start with the name gets it in front; other types pass unchanged.
    const std::string message = error.what();
    if (typeid(error) != typeid(Error) || message.rfind(options.name, 0) == 0) throw;
    throw Error(options.name + ": " + message);
  }
}

std::string canonical_form_key(const CanonicalFormOptions& o) {
  // Every option that changes the result, by name. A field added to an options struct must be added here.
  std::ostringstream k;
  k.precision(17);
  k << "method=" << o.method << ";knn=" << o.knn.k;
  if (o.method == "coulomb") {
    const CoulombCanonOptions& c = o.coulomb;
    k << ";scheme=" << to_string(c.scheme) << ";step_rule=" << to_string(c.step_rule)
      << ";step_gradient=" << to_string(c.step_gradient) << ";step_factor=" << c.step_factor
      << ";fixed_step=" << c.fixed_step << ";m=" << c.coulomb_steps << ";k=" << c.projection.steps
      << ";norm=" << static_cast<int>(c.projection.norm) << ";l1_floor=" << c.projection.l1_floor
      << ";dilation=" << c.projection.dilation << ";tear=" << c.tear_fraction << "," << c.tear_after << ","
      << c.tear_times << "," << c.tear_interval << ";tear_guard=" << to_string(c.tear_guard)
      << ";max_it=" << c.max_iterations << ";window=" << c.stop_window << ";tol=" << c.stop_tolerance
      << ";momentum=" << c.momentum << ";rigid=" << c.remove_rigid_motion
      << ";summation=" << static_cast<int>(c.energy.summation) << ";accuracy=" << c.energy.accuracy
      << ";floor=" << c.energy.min_distance << ";result_accuracy=" << c.result_accuracy;
  } else {
    k << ";geodesics=" << to_string(o.geodesics.method)
      << ";heat_mode=" << static_cast<int>(o.geodesics.heat_mode)
      << ";heat_t=" << o.geodesics.heat_time_factor << ";lanczos=" << o.cmds.lanczos_vectors
      << ";eig_tol=" << o.cmds.tolerance;
    if (o.method == "smacof")
      k << ";iters=" << o.smacof.max_iterations << ";tol=" << o.smacof.tolerance
        << ";target=" << o.smacof.target_stress << ";accel=" << to_string(o.smacof.acceleration)
        << ";window=" << o.smacof.extrapolation_window << ";weights=" << o.smacof.vertex_weights.size();
    // Added after the first caches were written: named only when not the default, so older keys still hold.
    if (o.method == "smacof" && o.smacof_init != "cmds") k << ";init=" << o.smacof_init;
    if (!o.distances_file.empty()) k << ";distances=" << file_content_hash(o.distances_file);
    if (o.method == "smacof" && o.smacof_weights != "uniform") k << ";weight_rule=" << o.smacof_weights;
  }
  return k.str();
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
  return cache_key({"canonical-form-v1", mesh_content_key(mesh), canonical_form_key(options)});
}

CanonicalForm cached_canonical_form(const DiskCache& cache, const Mesh& mesh,
                                    const CanonicalFormOptions& options, bool* was_cached,
                                    const DistanceMatrix* D, double D_seconds,
                                    const std::string& D_fallback) {
  const std::string key = canonical_form_cache_key(mesh, options);
  if (std::optional<nlohmann::json> hit = cache.get_json(key)) {
    // The repair (cheap) is redone for its report under this call's name, and so that --strict refuses.
    const RepairedMesh repaired = repair_for_canonical_form(mesh, options);
    if (was_cached) *was_cached = true;
    CanonicalForm form = form_from_json(*hit);
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
    co.progress = {};
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
    const bool mds = co.method != "coulomb" && co.distances_file.empty();
    if (mds && !(D_for && same_geodesics(*D_for, co)) &&
        !std::filesystem::exists(cache.entry_path(out.key))) {
      D_fallback.clear();
      D = geodesic_matrix(repair_for_canonical_form(mesh, co).mesh, co, &D_fallback);
      D_seconds = seconds_since(start);
      D_for = &co;
    }
    const bool use_D = mds && D_for && same_geodesics(*D_for, co);
    out.form = cached_canonical_form(cache, mesh, co, &out.cached, use_D ? &D : nullptr, D_seconds,
                                     use_D ? D_fallback : std::string());
    out.seconds = seconds_since(start);
  }
  return result;
}

}  // namespace cshapes
