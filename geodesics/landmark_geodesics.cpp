#include "cshapes/geodesics/landmark_geodesics.h"

#include <algorithm>
#include <exception>
#include <limits>
#include <memory>
#include <string>

#include "cshapes/support/error.h"
#include "cshapes/geodesics/fast_marching.h"
#include "cshapes/geodesics/heat_method.h"
#include "cshapes/support/timing.h"

namespace cshapes {

namespace {

void require_connected_for_rows(const Mesh& mesh) {
  const Components comp = connected_components(mesh.num_vertices(), mesh_edges(mesh.F));
  if (comp.count > 1)
    fail(
        "landmark geodesics: the mesh has ", comp.count, " connected components (largest ",
        comp.sizes[comp.largest()], " of ", mesh.num_vertices(),
        " vertices), so some distances are infinite; keep the largest component (mesh/mesh_repair.h; the CLI "
        "does unless --strict)");
}

}  // namespace

struct SingleSourceGeodesics::Impl {
  const Mesh& mesh;  // (no faces: a graph solver)
  GeodesicOptions options;
  std::unique_ptr<HeatMethod> heat;
  std::unique_ptr<FastMarching> fmm;
  Adjacency adj;
  Eigen::VectorXd edge_weights;
  double bound = 0;  // every geodesic is shorter than all edges together
};

SingleSourceGeodesics::SingleSourceGeodesics(const Mesh& mesh, const GeodesicOptions& options)
    : impl_(new Impl{mesh, options, nullptr, nullptr, {}, {}, 0}) {
  CSHAPES_REQUIRE(mesh.num_vertices() > 0, "landmark geodesics: the mesh has no vertices");
  require_connected_for_rows(mesh);
  if (std::string refusal = geodesic_method_refusal(mesh, options.method); !refusal.empty()) fail(refusal);
  const Edges E = mesh_edges(mesh.F);
  impl_->bound = edge_lengths(mesh.V, E).sum() * (1 + 1e-6);
  switch (options.method) {
    case GeodesicMethod::Heat: {
      HeatMethodOptions ho;
      ho.time_factor = options.heat_time_factor;
      ho.intrinsic_delaunay = options.heat_mode == CgalHeatMode::IntrinsicDelaunay;
      ho.progress = polls_of(options.progress);  // a stop heard in the factorisations and each solve
      impl_->heat = std::make_unique<HeatMethod>(mesh, ho);
      break;
    }
    case GeodesicMethod::FastMarching:
      impl_->fmm = std::make_unique<FastMarching>(mesh);
      break;
    case GeodesicMethod::Graph:
      impl_->adj = adjacency(mesh.num_vertices(), E);
      impl_->edge_weights = edge_lengths(mesh.V, E);
      break;
    case GeodesicMethod::HeatCgal:
    case GeodesicMethod::Exact:
      break;  // CGAL's solvers are built per source by geodesic_distances (not thread-safe to share)
  }
}

SingleSourceGeodesics::SingleSourceGeodesics(const Points& V, const Edges& E)
    : graph_points_(std::make_unique<Mesh>()) {
  graph_points_->V = V;
  GeodesicOptions options;
  options.method = GeodesicMethod::Graph;
  impl_.reset(new Impl{*graph_points_, options, nullptr, nullptr, {}, {}, 0});
  const Index n = V.rows();
  CSHAPES_REQUIRE(n > 0, "landmark geodesics: no points");
  const Components comp = connected_components(n, E);
  CSHAPES_REQUIRE(comp.count == 1, "landmark geodesics: the graph has ", comp.count,
                  " connected components (largest ", comp.sizes[comp.largest()], " of ", n, " points)");
  impl_->adj = adjacency(n, E);
  impl_->edge_weights = edge_lengths(V, E);
  impl_->bound = impl_->edge_weights.sum() * (1 + 1e-6);
}

SingleSourceGeodesics::~SingleSourceGeodesics() = default;

Index SingleSourceGeodesics::num_vertices() const {
  return impl_->mesh.num_vertices();
}

Eigen::VectorXd SingleSourceGeodesics::distances(int source) const {
  const Impl& im = *impl_;
  const Index n = im.mesh.num_vertices();
  CSHAPES_REQUIRE(source >= 0 && source < n, "landmark geodesics: source vertex ", source,
                  " out of range 0..", n - 1);
  Eigen::VectorXd d;
  if (im.heat)
    d = im.heat->distances({source});
  else if (im.fmm)
    d = im.fmm->distances({source});
  else if (im.options.method == GeodesicMethod::Graph)
    d = dijkstra(n, im.adj, im.edge_weights, {source});
  else
    return geodesic_distances(im.mesh, {source}, im.options);  // checks its own result
  for (Index i = 0; i < n; ++i)
    if (!(d[i] <= im.bound))  // NaN too
      fail("landmark geodesics (", to_string(im.options.method), "): the distance from vertex ", source,
           " to vertex ", i, " is ", d[i], " on a connected mesh; try another geodesic method, e.g. fmm");
  return d;
}

Eigen::MatrixXf geodesic_rows_from(const Mesh& mesh, const std::vector<int>& landmarks,
                                   const GeodesicOptions& options) {
  SingleSourceGeodesics solver(mesh, options);
  Eigen::MatrixXf rows(static_cast<Index>(landmarks.size()), mesh.num_vertices());
  for (int l : landmarks)
    CSHAPES_REQUIRE(l >= 0 && l < mesh.num_vertices(), "landmark geodesics: landmark vertex ", l,
                    " out of range 0..", mesh.num_vertices() - 1);
  // Independent rows: in parallel (each solve is single-threaded); the first exception is rethrown after.
  std::exception_ptr error;
#pragma omp parallel for schedule(dynamic, 1)
  for (Index k = 0; k < rows.rows(); ++k) {
    try {
      rows.row(k) = solver.distances(landmarks[k]).cast<float>().transpose();
    } catch (...) {
#pragma omp critical(cshapes_landmark_rows_error)
      if (!error) error = std::current_exception();
    }
  }
  if (error) std::rethrow_exception(error);
  return rows;
}

LandmarkGeodesics landmark_geodesics(const Mesh& mesh, const LandmarkGeodesicsOptions& options) {
  const auto start = WallClock::now();
  CSHAPES_REQUIRE(options.count >= 1, "landmark geodesics: the number of landmarks must be at least 1, not ",
                  options.count);
  const SingleSourceGeodesics solver(mesh, options.geodesics);
  LandmarkGeodesics result =
      landmark_geodesics(solver, mesh.V, options.count, options.first_hint, options.geodesics.progress);
  result.seconds = seconds_since(start);
  return result;
}

bool before_by_position(const Points& V, Index a, Index b) {
  for (int k = 0; k < 3; ++k)
    if (V(a, k) != V(b, k)) return V(a, k) < V(b, k);
  return false;
}

Index argmax_by_position(const Eigen::VectorXd& value, const Points& V) {
  Index best = 0;
  for (Index i = 1; i < value.size(); ++i)
    if (value[i] > value[best] || (value[i] == value[best] && before_by_position(V, i, best))) best = i;
  return best;
}

Index central_vertex(const Points& V) {
  const Eigen::RowVector3d centroid = V.colwise().mean();
  return argmax_by_position(-(V.rowwise() - centroid).rowwise().squaredNorm().transpose(), V);
}

LandmarkGeodesics landmark_geodesics(const SingleSourceGeodesics& solver, const Points& V, Index count,
                                     int first_hint, const ProgressFn& progress) {
  const auto start = WallClock::now();
  const Index n = solver.num_vertices();
  CSHAPES_REQUIRE(count >= 1, "landmark geodesics: the number of landmarks must be at least 1, not ", count);
  CSHAPES_REQUIRE(V.rows() == n, "landmark geodesics: ", V.rows(), " points for ", n, " vertices");
  CSHAPES_REQUIRE(first_hint >= -1 && first_hint < n, "landmark geodesics: first_hint ", first_hint,
                  " out of range -1..", n - 1);
  if (first_hint < 0) first_hint = static_cast<int>(central_vertex(V));
  const Index L = std::min(count, n);
  LandmarkGeodesics result;
  result.rows.resize(L, n);
  result.landmarks.reserve(L);
  // nearest(i): distance from vertex i to its nearest landmark so far; the hint's row starts the sampling.
  Eigen::VectorXd nearest = solver.distances(first_hint);
  for (Index k = 0; k < L; ++k) {
    const Index next = argmax_by_position(nearest, V);
    result.landmarks.push_back(static_cast<int>(next));
    const Eigen::VectorXd row = solver.distances(static_cast<int>(next));
    result.rows.row(k) = row.cast<float>().transpose();
    nearest = k == 0 ? row : nearest.cwiseMin(row);
    if (progress) progress("landmark geodesics", static_cast<double>(k + 1), static_cast<double>(L));
  }
  result.coverage_radius = nearest.maxCoeff();
  result.seconds = seconds_since(start);
  return result;
}

}  // namespace cshapes
