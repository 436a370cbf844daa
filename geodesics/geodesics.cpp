#include "cshapes/geodesics/geodesics.h"

#include <algorithm>
#include <atomic>
#include <exception>
#include <limits>
#include <memory>
#include <queue>
#include <string>

#include "cshapes/support/error.h"
#include "cshapes/geodesics/fast_marching.h"
#include "cshapes/geodesics/heat_method.h"
#include "cshapes/mesh/unit_scale.h"

namespace cshapes {

namespace {

// Reports progress from inside an OpenMP loop, after every source. The progress function is also where a
// stop (Python's Ctrl-C) is heard, and one source is the unit a stop waits for: a report costs a lock (well
// under a microsecond), a source of fast marching on 1,000,000 vertices about a second, so reporting only
// every 64 sources made a stop wait for minutes on large meshes (the printer itself reports at most 4 times a
// second).
class ProgressCounter {
 public:
  ProgressCounter(const ProgressFn& fn, Index total) : fn_(fn), total_(total) {}
  void add(Index count = 1) {
    Index finished = done_ += count;
    if (fn_)
      report_progress_in_parallel(fn_, "geodesics", static_cast<double>(finished),
                                  static_cast<double>(total_));
  }

 private:
  const ProgressFn& fn_;
  Index total_;
  std::atomic<Index> done_{0};
};

// Runs body(s) for every source s in parallel; the first exception is rethrown after the loop.
template <typename Body>
void parallel_over_sources(Index n, Body&& body) {
  std::exception_ptr error;
  std::atomic<bool> failed{false};
#pragma omp parallel for schedule(dynamic, 8)
  for (Index s = 0; s < n; ++s) {
    if (failed) continue;
    try {
      body(s);
    } catch (...) {
#pragma omp critical(cshapes_geodesics_error)
      if (!error) error = std::current_exception();
      failed = true;
    }
  }
  if (error) std::rethrow_exception(error);
}

bool uses_cgal_heat(const GeodesicOptions& o) {
  return o.method == GeodesicMethod::HeatCgal;
}

HeatMethodOptions heat_options(const GeodesicOptions& o) {
  HeatMethodOptions ho;
  ho.time_factor = o.heat_time_factor;
  ho.intrinsic_delaunay = o.heat_mode == CgalHeatMode::IntrinsicDelaunay;
  ho.progress = polls_of(o.progress);  // a stop heard in the set-up and solves; reports: the caller's
  return ho;
}

// CGAL's algorithms want one connected manifold: run them on each component that holds a source.
template <typename Solve>
Eigen::VectorXd per_component(const Mesh& mesh, const std::vector<int>& sources, Solve&& solve) {
  Components comp = connected_components(mesh.num_vertices(), mesh_edges(mesh.F));
  if (comp.count == 1) return solve(mesh, sources);
  Eigen::VectorXd d = Eigen::VectorXd::Constant(mesh.num_vertices(), std::numeric_limits<double>::infinity());
  std::vector<char> done(comp.count, 0);
  for (int s : sources) {
    CSHAPES_REQUIRE(s >= 0 && s < mesh.num_vertices(), "geodesics: source vertex ", s, " out of range 0..",
                    mesh.num_vertices() - 1);
    int label = comp.label[s];
    if (done[label]) continue;
    done[label] = 1;
    Submesh sub = extract_component(mesh, comp, label);
    std::vector<int> local_of(mesh.num_vertices(), -1);
    for (size_t k = 0; k < sub.vertex_map.size(); ++k) local_of[sub.vertex_map[k]] = static_cast<int>(k);
    std::vector<int> local_sources;
    for (int t : sources)
      if (comp.label[t] == label) local_sources.push_back(local_of[t]);
    if (sub.mesh.num_faces() == 0) {  // an isolated vertex
      for (int t : local_sources) d[sub.vertex_map[t]] = 0;
      continue;
    }
    Eigen::VectorXd local = solve(sub.mesh, local_sources);
    for (size_t k = 0; k < sub.vertex_map.size(); ++k) d[sub.vertex_map[k]] = local[k];
  }
  return d;
}

// What to try when `method` returned a non-finite distance on a connected mesh.
std::string non_finite_advice(GeodesicMethod method) {
  switch (method) {
    case GeodesicMethod::HeatCgal:
      return "CGAL's heat method returns NaN or DBL_MAX where a normalised gradient is undefined (its heat "
             "underflows on long or finely meshed shapes; tiny meshes such as a tetrahedron fail too); use "
             "--method heat (ours continues by fast marching there) or fmm";
    case GeodesicMethod::Heat:
      return "the heat method failed numerically on this mesh; use --method fmm or exact, and please report "
             "the mesh";
    default:
      return "please report the mesh; --method heat or graph may serve meanwhile";
  }
}

// An upper bound of every geodesic distance on a connected mesh: the sum of its edge lengths (a path along
// edges visits each edge at most once). CGAL's heat method, where its heat underflows, returns NaN gradients
// and then DBL_MAX distances, finite but no distance.
double distance_bound(const Mesh& mesh) {
  return edge_lengths(mesh.V, mesh_edges(mesh.F)).sum() * (1 + 1e-6);
}

// Throws unless every distance in `d` from `sources` is finite and at most `bound` where it must be: on the
// vertices of the components that hold a source (`label` from connected_components; all vertices when label
// is empty).
template <typename Vector>
void require_finite(const Vector& d, const std::vector<int>& label, const std::vector<int>& sources,
                    GeodesicMethod method, double bound) {
  const auto valid = [bound](double x) { return x <= bound; };  // false for NaN too
  if (d.allFinite() && static_cast<double>(d.maxCoeff()) <= bound) return;
  std::vector<char> reached;
  if (!label.empty()) {
    reached.assign(*std::max_element(label.begin(), label.end()) + 1, 0);
    for (int s : sources) reached[label[s]] = 1;
  }
  for (Index i = 0; i < d.size(); ++i) {
    if (valid(static_cast<double>(d[i])) || (!label.empty() && !reached[label[i]])) continue;
    std::string from = std::to_string(sources[0]);
    if (sources.size() > 1)
      from = "the nearest of " + std::to_string(sources.size()) + " sources (first " + from + ")";
    fail("geodesics (", to_string(method), "): the distance from vertex ", from, " to vertex ", i, " is ",
         static_cast<double>(d[i]),
         std::isfinite(static_cast<double>(d[i])) ? " (longer than all edges together)" : "",
         " although they are connected; ", non_finite_advice(method));
  }
}

}  // namespace

GeodesicMethod parse_geodesic_method(const std::string& name) {
  if (name == "heat") return GeodesicMethod::Heat;
  if (name == "heat-cgal") return GeodesicMethod::HeatCgal;
  if (name == "fmm") return GeodesicMethod::FastMarching;
  if (name == "exact") return GeodesicMethod::Exact;
  if (name == "graph") return GeodesicMethod::Graph;
  fail("unknown geodesic method '", name, "'; known: heat, heat-cgal, fmm, exact, graph");
}

const std::vector<std::string>& geodesic_method_names() {
  static const std::vector<std::string> names = {"heat", "heat-cgal", "fmm", "exact", "graph"};
  return names;
}

std::string to_string(GeodesicMethod method) {
  switch (method) {
    case GeodesicMethod::Heat:
      return "heat";
    case GeodesicMethod::HeatCgal:
      return "heat-cgal";
    case GeodesicMethod::FastMarching:
      return "fmm";
    case GeodesicMethod::Exact:
      return "exact";
    case GeodesicMethod::Graph:
      return "graph";
  }
  return "?";
}

Eigen::VectorXd dijkstra(Index num_vertices, const Adjacency& adj, const Eigen::VectorXd& edge_weights,
                         const std::vector<int>& sources) {
  const double inf = std::numeric_limits<double>::infinity();
  Eigen::VectorXd dist = Eigen::VectorXd::Constant(num_vertices, inf);
  using Item = std::pair<double, int>;
  std::priority_queue<Item, std::vector<Item>, std::greater<Item>> queue;
  for (int s : sources) {
    CSHAPES_REQUIRE(s >= 0 && s < num_vertices, "geodesics: source vertex ", s, " out of range 0..",
                    num_vertices - 1);
    dist[s] = 0;
    queue.emplace(0.0, s);
  }
  while (!queue.empty()) {
    auto [d, i] = queue.top();
    queue.pop();
    if (d > dist[i]) continue;
    for (int k = adj.offsets[i]; k < adj.offsets[i + 1]; ++k) {
      int j = adj.neighbors[k];
      double nd = d + edge_weights[adj.edge_ids[k]];
      if (nd < dist[j]) {
        dist[j] = nd;
        queue.emplace(nd, j);
      }
    }
  }
  return dist;
}

std::string geodesic_method_refusal(const Mesh& mesh, GeodesicMethod method) {
  if ((method != GeodesicMethod::Exact && method != GeodesicMethod::HeatCgal) || mesh.num_faces() == 0)
    return "";
  double length_sum = 0;
  for (Index f = 0; f < mesh.num_faces(); ++f)
    for (int k = 0; k < 3; ++k)
      length_sum += (mesh.V.row(mesh.F(f, k)) - mesh.V.row(mesh.F(f, (k + 1) % 3))).norm();
  const double h = length_sum / (3.0 * static_cast<double>(mesh.num_faces()));
  Index degenerate = 0, first = -1;
  for (Index f = 0; f < mesh.num_faces(); ++f) {
    const Eigen::Vector3d a = mesh.V.row(mesh.F(f, 0)), b = mesh.V.row(mesh.F(f, 1)),
                          c = mesh.V.row(mesh.F(f, 2));
    if (!(0.5 * (b - a).cross(c - a).norm() >= kExactMinFaceArea * h * h)) {
      if (first < 0) first = f;
      ++degenerate;
    }
  }
  if (degenerate == 0) return "";
  return detail::concat(
      method == GeodesicMethod::Exact ? "exact geodesics (CGAL's Surface_mesh_shortest_path)"
                                      : "CGAL's heat method (Heat_method_3)",
      " need faces of positive area; ", degenerate, " face(s) have (nearly) zero area, the first face ",
      first, " (vertices ", mesh.F(first, 0), ", ", mesh.F(first, 1), ", ", mesh.F(first, 2),
      "); use --method heat or fmm, or repair the mesh (without --strict, cshapes drops "
      "zero-area faces)");
}

namespace {

Eigen::VectorXd unchecked_geodesic_distances(const Mesh& mesh, const std::vector<int>& sources,
                                             const GeodesicOptions& options) {
  CSHAPES_REQUIRE(!sources.empty(), "geodesics: no source vertex given");
  if (std::string refusal = geodesic_method_refusal(mesh, options.method); !refusal.empty()) fail(refusal);
  for (int s : sources)
    CSHAPES_REQUIRE(s >= 0 && s < mesh.num_vertices(), "geodesics: source vertex ", s, " out of range 0..",
                    mesh.num_vertices() - 1);
  if (uses_cgal_heat(options)) {
    return per_component(mesh, sources, [&](const Mesh& m, const std::vector<int>& s) {
      return cgal_heat_method(m, s, options.heat_mode);
    });
  }
  switch (options.method) {
    case GeodesicMethod::Heat: {
      return HeatMethod(mesh, heat_options(options)).distances(sources);
    }
    case GeodesicMethod::HeatCgal:
      break;  // handled above
    case GeodesicMethod::FastMarching:
      return fast_marching(mesh, sources);
    case GeodesicMethod::Exact:
      return per_component(mesh, sources,
                           [](const Mesh& m, const std::vector<int>& s) { return exact_geodesics(m, s); });
    case GeodesicMethod::Graph: {
      Edges E = mesh_edges(mesh.F);
      return dijkstra(mesh.num_vertices(), adjacency(mesh.num_vertices(), E), edge_lengths(mesh.V, E),
                      sources);
    }
  }
  fail("geodesics: unsupported method");
}

}  // namespace

Eigen::VectorXd geodesic_distances(const Mesh& mesh, const std::vector<int>& sources,
                                   const GeodesicOptions& options) {
  // Computed at unit size (mesh/unit_scale.h): every method is scale-equivariant there, and none underflows
  // or overflows at any finite scale (fast marching returned zeros at 1e-300 and infinities at 1e154).
  if (const double scale = power_of_two_unit_scale(mesh.V); scale != 1) {
    Eigen::VectorXd d = geodesic_distances(Mesh{mesh.V * scale, mesh.F}, sources, options) / scale;
    for (Index i = 0; i < d.size(); ++i)
      CSHAPES_REQUIRE(!std::isinf(d[i]) || std::isinf(d[i] * scale), "geodesics: the distance to vertex ", i,
                      " exceeds the largest double (the mesh's coordinates reach ", mesh.V.cwiseAbs().maxCoeff(),
                      "); scale the mesh down");
    return d;
  }
  // A poll before each solve (support/progress.h): the callers that solve one source after another (gluing's
  // geodesic tests, correspondence errors, landmark rows) hear a stop within one solve.
  report_progress_in_parallel(options.progress, "", 0, 0);
  Eigen::VectorXd d = unchecked_geodesic_distances(mesh, sources, options);
  require_finite(d, connected_components(mesh.num_vertices(), mesh_edges(mesh.F)).label, sources,
                 options.method, distance_bound(mesh));
  return d;
}

void symmetrize_distances(DistanceMatrix& D) {
  CSHAPES_REQUIRE(D.rows() == D.cols(), "symmetrize_distances: matrix is ", D.rows(), "x", D.cols());
  const Index n = D.rows(), tile = 64;
  const Index tiles = (n + tile - 1) / tile;
  // Tile (I, J) with I >= J is averaged with its mirror (J, I); each pair is touched by one thread only.
#pragma omp parallel for schedule(dynamic, 1)
  for (Index J = 0; J < tiles; ++J)
    for (Index I = J; I < tiles; ++I) {
      const Index j0 = J * tile, j1 = std::min(n, j0 + tile), i0 = I * tile, i1 = std::min(n, i0 + tile);
      for (Index j = j0; j < j1; ++j)
        for (Index i = std::max(i0, j + 1); i < i1; ++i) {
          const float m = 0.5f * (D(i, j) + D(j, i));
          D(i, j) = m;
          D(j, i) = m;
        }
    }
  D.diagonal().setZero();
}

namespace {

// Refuses a mesh scaled by `scale` (to unit size) whose distances, taken back to its own units, would fall
// outside float32's normal range (about 1.2e-38 … 3.4e38), which the distance matrix stores.
void check_float_range(const Mesh& unit, double scale) {
  const Eigen::VectorXd lengths = edge_lengths(unit.V, mesh_edges(unit.F));
  double shortest = std::numeric_limits<double>::infinity();
  for (Index e = 0; e < lengths.size(); ++e)
    if (lengths[e] > 0) shortest = std::min(shortest, lengths[e]);
  const double longest = lengths.sum();  // no distance along the mesh exceeds all edges together
  if (lengths.size() && (shortest / scale < std::numeric_limits<float>::min() ||
                         longest / scale > std::numeric_limits<float>::max()))
    fail("all-pairs geodesics: this mesh's distances (edges of ", shortest / scale, " to paths of up to ",
         longest / scale, ") lie outside the range of float32, which the distance matrix stores (",
         std::numeric_limits<float>::min(), " to ", std::numeric_limits<float>::max(), "); ",
         longest / shortest < 1e70 ? "scale the mesh (one source's distances work at any scale)"
                                   : "its edge lengths span more orders of magnitude than float32 holds");
}

// The columns of D by CGAL's heat method: one solver (mesh copy + two factorisations) per thread, since
// CGAL's objects are not thread-safe.
void cgal_heat_columns(const Mesh& mesh, const GeodesicOptions& options, double bound,
                       ProgressCounter& progress, DistanceMatrix& D) {
  const Index n = mesh.num_vertices();
  std::exception_ptr error;
  std::atomic<bool> failed{false};
#pragma omp parallel
  {
    std::unique_ptr<CgalHeatMethod> solver;
    try {
      solver = std::make_unique<CgalHeatMethod>(mesh, options.heat_mode);
    } catch (...) {
#pragma omp critical(cshapes_geodesics_error)
      if (!error) error = std::current_exception();
    }
#pragma omp for schedule(dynamic, 8)
    for (Index s = 0; s < n; ++s) {
      if (!solver || failed) continue;
      try {
        D.col(s) = solver->distances({static_cast<int>(s)}).cast<float>();
        require_finite(D.col(s), {}, {static_cast<int>(s)}, options.method, bound);
        progress.add();
      } catch (...) {
#pragma omp critical(cshapes_geodesics_error)
        if (!error) error = std::current_exception();
        failed = true;
      }
    }
  }
  if (error) std::rethrow_exception(error);
}

// The columns of D by our own methods, each column one source.
void own_method_columns(const Mesh& mesh, const GeodesicOptions& options, double bound,
                        ProgressCounter& progress, DistanceMatrix& D) {
  const Index n = mesh.num_vertices();
  auto store = [&](Index s, const auto& column) {
    D.col(s) = column.template cast<float>();
    require_finite(D.col(s), {}, {static_cast<int>(s)}, options.method, bound);
    progress.add();
  };
  switch (options.method) {
    case GeodesicMethod::Heat: {
      HeatMethod heat(mesh, heat_options(options));
      std::vector<int> sources(n);
      for (Index s = 0; s < n; ++s) sources[s] = static_cast<int>(s);
      heat.for_each_source(sources,
                           [&](Index k, const Eigen::Ref<const Eigen::VectorXd>& column) { store(k, column); });
      break;
    }
    case GeodesicMethod::HeatCgal:
      break;  // cgal_heat_columns
    case GeodesicMethod::FastMarching: {
      FastMarching fmm(mesh);
      parallel_over_sources(n, [&](Index s) { store(s, fmm.distances({static_cast<int>(s)})); });
      break;
    }
    case GeodesicMethod::Exact:
      parallel_over_sources(n, [&](Index s) { store(s, exact_geodesics(mesh, {static_cast<int>(s)})); });
      break;
    case GeodesicMethod::Graph: {
      Edges E = mesh_edges(mesh.F);
      Adjacency adj = adjacency(n, E);
      Eigen::VectorXd w = edge_lengths(mesh.V, E);
      parallel_over_sources(n, [&](Index s) { store(s, dijkstra(n, adj, w, {static_cast<int>(s)})); });
      break;
    }
  }
}

}  // namespace

DistanceMatrix all_pairs_geodesics(const Mesh& mesh, const GeodesicOptions& options) {
  const Index n = mesh.num_vertices();
  CSHAPES_REQUIRE(n > 0, "all-pairs geodesics: the mesh has no vertices");
  // Computed at unit size, as geodesic_distances; the matrix holds float32, so distances outside its normal
  // range are refused up front rather than stored as 0 or infinity.
  if (const double scale = power_of_two_unit_scale(mesh.V); scale != 1) {
    const Mesh unit{mesh.V * scale, mesh.F};
    check_float_range(unit, scale);
    DistanceMatrix D = all_pairs_geodesics(unit, options);
    D *= static_cast<float>(1 / scale);  // a power of two: exact in float within the range checked above
    return D;
  }
  {
    Components comp = connected_components(n, mesh_edges(mesh.F));
    if (comp.count > 1)
      fail("all-pairs geodesics: the mesh has ", comp.count, " connected components (largest ",
           comp.sizes[comp.largest()], " of ", n,
           " vertices), so some distances are infinite; keep the largest component (mesh/mesh_repair.h; the CLI "
           "does unless --strict)");
  }
  if (std::string refusal = geodesic_method_refusal(mesh, options.method); !refusal.empty()) fail(refusal);
  require_memory(distance_matrix_bytes(n), "all-pairs geodesics on " + std::to_string(n) + " vertices");
  const double bound = distance_bound(mesh);
  DistanceMatrix D = uninitialized_distance_matrix(n, n);
  ProgressCounter progress(options.progress, n);
  if (uses_cgal_heat(options))
    cgal_heat_columns(mesh, options, bound, progress, D);
  else
    own_method_columns(mesh, options, bound, progress, D);
  symmetrize_distances(D);
  return D;
}

}  // namespace cshapes
