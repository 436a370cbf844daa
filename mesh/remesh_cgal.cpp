// CGAL side of mesh/remesh.h: isotropic remeshing, edge-collapse simplification, AABB-tree distances and the
// exact self-intersection test. The only translation unit of the remeshing code that sees CGAL types.
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Polygon_mesh_processing/detect_features.h>
#include <CGAL/Polygon_mesh_processing/remesh.h>
#include <CGAL/Polygon_mesh_processing/self_intersections.h>
#include <CGAL/Polygon_mesh_processing/tangential_relaxation.h>
#include <CGAL/Surface_mesh.h>
#include <CGAL/Surface_mesh_simplification/Policies/Edge_collapse/Edge_length_cost.h>
#include <CGAL/Surface_mesh_simplification/Policies/Edge_collapse/LindstromTurk.h>
#include <CGAL/Surface_mesh_simplification/Policies/Edge_collapse/Midpoint_placement.h>
#include <CGAL/Surface_mesh_simplification/edge_collapse.h>

#include <omp.h>

#include <algorithm>
#include <cmath>
#include <exception>
#include <iterator>
#include <optional>
#include <unordered_map>

#include "cshapes/support/distance_matrix.h"
#include "cshapes/support/error.h"
#include "cshapes/mesh/io.h"
#include "cshapes/mesh/locate_on_surface.h"
#include "cshapes/mesh/remesh.h"
#include "cshapes/mesh/surface_mesh_cgal.h"
#include "cshapes/mesh/unit_scale.h"

namespace cshapes {
namespace {

using cgal::Kernel;
using cgal::Point3;
using cgal::SurfaceMesh;
namespace PMP = CGAL::Polygon_mesh_processing;
namespace SMS = CGAL::Surface_mesh_simplification;

// Peak memory per target vertex (input, remeshed surface and best attempt as CGAL Surface_meshes, AABB trees,
// the result as Eigen arrays, the Hausdorff measure): cat0 remeshed to 50,000 and 200,000 vertices peaked at
// 45 and 161 MB, 0.77 KB per added vertex; rounded up.
constexpr double kRemeshBytesPerVertex = 1000;

// Copies a (possibly garbage-holding) Surface_mesh into Eigen arrays, vertices in index order.
Mesh from_cgal(const SurfaceMesh& sm) {
  Mesh mesh;
  mesh.V.resize(sm.number_of_vertices(), 3);
  std::unordered_map<std::size_t, int> index;
  index.reserve(sm.number_of_vertices());
  int k = 0;
  for (auto v : sm.vertices()) {
    const Point3& p = sm.point(v);
    mesh.V.row(k) << p.x(), p.y(), p.z();
    index[static_cast<std::size_t>(v)] = k++;
  }
  mesh.F.resize(sm.number_of_faces(), 3);
  int f = 0;
  for (auto face : sm.faces()) {
    int c = 0;
    for (auto v : CGAL::vertices_around_face(sm.halfedge(face), sm))
      mesh.F(f, c++) = index.at(static_cast<std::size_t>(v));
    ++f;
  }
  return mesh;
}

// Stops the collapse when the mesh has no more than `target` vertices (exact, unlike an edge-count ratio).
// CGAL's remeshing and edge collapse run for seconds without a callback of their own; a stop (Ctrl-C in
// Python, support/progress.h) must be heard within a fraction of a second. A Poller calls the progress function
// as a poll (empty stage) every kPollEvery ticks; the calls below tick it once per collapse and once per point
// CGAL writes, which leaves the results bit for bit what they are without it.
class Poller {
 public:
  explicit Poller(const ProgressFn& fn) : fn_(fn) {}
  void tick() const {
    if (fn_ && ++ticks_ % kPollEvery == 0) fn_("", 0, 0);
  }

 private:
  static constexpr std::size_t kPollEvery = 4096;
  const ProgressFn& fn_;
  mutable std::size_t ticks_ = 0;
};

struct VertexCountStop {
  const SurfaceMesh* mesh;
  std::size_t target;
  const Poller* poller = nullptr;
  template <typename Cost, typename Profile>
  bool operator()(const Cost&, const Profile&, std::size_t, std::size_t) const {
    if (poller) poller->tick();
    return mesh->number_of_vertices() <= target;
  }
};

// The mesh's point map, with a tick of the poller on every write (isotropic remeshing writes a point for
// every split, collapse, relaxation and projection).
struct PollingPointMap {
  using key_type = SurfaceMesh::Vertex_index;
  using value_type = Point3;
  using reference = const Point3&;
  using category = boost::read_write_property_map_tag;
  SurfaceMesh::Property_map<SurfaceMesh::Vertex_index, Point3> points;
  const Poller* poller;
  friend reference get(const PollingPointMap& m, key_type v) { return m.points[v]; }
  friend void put(const PollingPointMap& m, key_type v, const value_type& p) {
    m.poller->tick();
    m.points[v] = p;
  }
};

// Smallest angle (radians) of triangle (a, b, c).
double min_triangle_angle(const Eigen::Vector3d& a, const Eigen::Vector3d& b, const Eigen::Vector3d& c) {
  auto angle = [](const Eigen::Vector3d& p, const Eigen::Vector3d& q, const Eigen::Vector3d& r) {
    Eigen::Vector3d u = q - p, w = r - p;
    return std::atan2(u.cross(w).norm(), u.dot(w));
  };
  return std::min({angle(a, b, c), angle(b, c, a), angle(c, a, b)});
}

// Flips edges of badly shaped triangles where the surface is nearly flat (the two faces' normals within
// max_dihedral_deg), when the flip raises the smaller of the two triangles' smallest angles. Sharp edges and
// feature lines are never flipped (not flat), vertices do not move: the shape is unchanged up to the
// flatness.
void improve_by_flips(Mesh& mesh, double bad_angle_deg, double max_dihedral_deg, int passes) {
  const double bad = bad_angle_deg * 3.14159265358979323846 / 180;
  const double cos_flat = std::cos(max_dihedral_deg * 3.14159265358979323846 / 180);
  auto key = [](int i, int j) {
    return (static_cast<std::uint64_t>(static_cast<std::uint32_t>(i)) << 32) | static_cast<std::uint32_t>(j);
  };
  std::unordered_map<std::uint64_t, int> face_of;  // directed edge i->j -> face containing it
  for (Index f = 0; f < mesh.num_faces(); ++f)
    for (int c = 0; c < 3; ++c) face_of[key(mesh.F(f, c), mesh.F(f, (c + 1) % 3))] = static_cast<int>(f);
  auto P = [&](int i) { return Eigen::Vector3d(mesh.V.row(i)); };
  auto normal = [&](int a, int b, int c) { return (P(b) - P(a)).cross(P(c) - P(a)).normalized(); };
  for (int pass = 0; pass < passes; ++pass) {
    int flips = 0;
    for (Index f1 = 0; f1 < mesh.num_faces(); ++f1) {
      if (min_triangle_angle(P(mesh.F(f1, 0)), P(mesh.F(f1, 1)), P(mesh.F(f1, 2))) >= bad) continue;
      double best_gain = 1e-9;
      int best_c = -1;
      for (int c = 0; c < 3; ++c) {
        const int i = mesh.F(f1, c), j = mesh.F(f1, (c + 1) % 3), k = mesh.F(f1, (c + 2) % 3);
        auto it = face_of.find(key(j, i));
        if (it == face_of.end()) continue;  // border edge
        const int f2 = it->second;
        int l = -1;
        for (int d = 0; d < 3; ++d)
          if (mesh.F(f2, d) != i && mesh.F(f2, d) != j) l = mesh.F(f2, d);
        if (l < 0 || l == k || face_of.count(key(k, l)) || face_of.count(key(l, k))) continue;
        const Eigen::Vector3d n1 = normal(i, j, k), n2 = normal(j, i, l);
        // A cap (k almost on the edge ij: its angle at k near 180°) has no reliable normal and almost no
        // area; flipping its long edge splits the neighbour in two and changes the surface by about nothing.
        const Eigen::Vector3d ki = P(i) - P(k), kj = P(j) - P(k);
        const bool cap = std::atan2(ki.cross(kj).norm(), ki.dot(kj)) > 160 * 3.14159265358979323846 / 180;
        if (!cap && n1.dot(n2) < cos_flat) continue;
        const Eigen::Vector3d n = cap ? n2 : Eigen::Vector3d((n1 + n2).normalized());
        if (normal(k, i, l).dot(n) <= 0.5 || normal(l, j, k).dot(n) <= 0.5) continue;  // the flip would fold
        double before = std::min(min_triangle_angle(P(i), P(j), P(k)), min_triangle_angle(P(j), P(i), P(l)));
        double after = std::min(min_triangle_angle(P(k), P(i), P(l)), min_triangle_angle(P(l), P(j), P(k)));
        if (after - before > best_gain) best_gain = after - before, best_c = c;
      }
      if (best_c < 0) continue;
      const int i = mesh.F(f1, best_c), j = mesh.F(f1, (best_c + 1) % 3), k = mesh.F(f1, (best_c + 2) % 3);
      const int f2 = face_of.at(key(j, i));
      int l = -1;
      for (int d = 0; d < 3; ++d)
        if (mesh.F(f2, d) != i && mesh.F(f2, d) != j) l = mesh.F(f2, d);
      for (int f : {static_cast<int>(f1), f2})
        for (int c = 0; c < 3; ++c) face_of.erase(key(mesh.F(f, c), mesh.F(f, (c + 1) % 3)));
      // (i, j, k) + (j, i, l) -> (k, i, l) + (l, j, k): same orientation, edge ij replaced by kl.
      mesh.F.row(f1) << k, i, l;
      mesh.F.row(f2) << l, j, k;
      for (int f : {static_cast<int>(f1), f2})
        for (int c = 0; c < 3; ++c) face_of[key(mesh.F(f, c), mesh.F(f, (c + 1) % 3))] = f;
      ++flips;
    }
    if (flips == 0) break;
  }
}

// Largest distance from the sample points of `from` (vertices, edge midpoints, centroids) to the surface
// `to`, located in blocks (the samples of a million-vertex mesh are never all held at once).
double one_sided_distance(const Mesh& from, const SurfaceLocator& to) {
  constexpr Index kBlock = 65536;
  double worst = 0;
  Points block(kBlock, 3);
  Index filled = 0;
  auto flush = [&] {
    if (filled == 0) return;
    worst = std::max(worst, to.locate(block.topRows(filled)).distance.maxCoeff());
    filled = 0;
  };
  auto add = [&](const Eigen::Vector3d& p) {
    block.row(filled++) = p.transpose();
    if (filled == kBlock) flush();
  };
  for (Index i = 0; i < from.num_vertices(); ++i) add(from.V.row(i).transpose());
  for (Index f = 0; f < from.num_faces(); ++f) {
    Eigen::Vector3d a = from.V.row(from.F(f, 0)), b = from.V.row(from.F(f, 1)), c = from.V.row(from.F(f, 2));
    add((a + b + c) / 3);
    add((a + b) / 2);  // each interior edge twice: harmless
    add((b + c) / 2);
    add((c + a) / 2);
  }
  flush();
  return worst;
}

}  // namespace

namespace {

// One full run (edge-length search, collapse to the target) on the prepared input, with sharp edges above
// feature_angle_deg kept as constraints (0: none).
RemeshResult remesh_once(const SurfaceMesh& input, const Mesh& mesh, const RemeshOptions& o,
                         double feature_angle_deg) {
  const double area = surface_area(mesh.V, mesh.F);  // of the original: the simplified one is barely smaller
  const auto target = static_cast<double>(o.target_vertices);
  // Aim a little above the target so that the final collapse, not a refinement, fixes the count.
  const double aim = target * (1 + 0.5 * o.tolerance) + 2;

  RemeshResult result;
  // Equilateral triangles with F ≈ 2V: A = V (√3/2) L².
  double length = std::sqrt(2 * area / (std::sqrt(3.0) * aim));
  SurfaceMesh best;
  Index best_count = -1;
  const Poller poller(o.progress);
  for (int attempt = 0; attempt < o.max_attempts; ++attempt) {
    SurfaceMesh sm = input;
    // Sharp edges (thin fins such as ears, crease lines) are kept as polylines that may be split but not
    // smoothed away; without them the tip of a thin part is cut off by about one edge length.
    auto sharp = sm.add_property_map<SurfaceMesh::Edge_index, bool>("e:sharp", false).first;
    if (feature_angle_deg > 0) PMP::detect_sharp_edges(sm, feature_angle_deg, sharp);
    PMP::isotropic_remeshing(faces(sm), length, sm,
                             PMP::parameters::vertex_point_map(PollingPointMap{sm.points(), &poller})
                                 .number_of_iterations(o.relaxation_iterations)
                                 .protect_constraints(o.protect_border)
                                 .edge_is_constrained_map(sharp)
                                 .number_of_relaxation_steps(1));
    sm.remove_property_map(sharp);
    sm.collect_garbage();
    auto count = static_cast<Index>(sm.number_of_vertices());
    ++result.attempts;
    result.target_edge_length = length;
    if (o.progress) o.progress("remesh", attempt + 1, o.max_attempts);
    bool above = count >= o.target_vertices;
    // Keep the attempt closest above the target (collapsing few edges keeps the remesher's angles).
    if (above && (best_count < 0 || count < best_count)) {
      best = sm;
      best_count = count;
    }
    if (above && count <= target * (1 + 3 * o.tolerance) + 4) break;
    // N ∝ 1/L²; damp the step so that the noise of the count does not make it oscillate.
    double ratio = std::sqrt(static_cast<double>(count) / aim);
    length *= std::clamp(ratio, 0.5, 2.0);
  }
  CSHAPES_REQUIRE(best_count >= 0, "remesh: could not reach ", o.target_vertices, " vertices in ",
                  o.max_attempts, " attempts (last edge length ", length, ")");
  result.remeshed_vertices = best_count;

  if (best_count > o.target_vertices) {
    VertexCountStop stop{&best, static_cast<std::size_t>(o.target_vertices), &poller};
    SMS::LindstromTurk_cost<SurfaceMesh> cost;
    SMS::LindstromTurk_placement<SurfaceMesh> placement;
    result.collapsed_edges =
        SMS::edge_collapse(best, stop, CGAL::parameters::get_cost(cost).get_placement(placement));
    best.collect_garbage();
    PMP::tangential_relaxation(best, PMP::parameters::number_of_iterations(1));
  }
  result.mesh = from_cgal(best);
  improve_by_flips(result.mesh, 20, 15, 5);
  Index got = result.mesh.num_vertices();
  CSHAPES_REQUIRE(std::abs(static_cast<double>(got) - target) <= o.tolerance * target + 1, "remesh: got ",
                  got, " vertices, more than ", o.tolerance * 100, "% away from ", o.target_vertices);
  return result;
}

}  // namespace

double remesh_memory_bytes(Index target_vertices) {
  return kRemeshBytesPerVertex * static_cast<double>(std::max<Index>(target_vertices, 0));
}

namespace {
// remesh() on a mesh of about unit size (its options and the mesh already checked).
RemeshResult remesh_at_unit_size(const Mesh& mesh, const RemeshOptions& o);

// The feature-line runs' angles, as factors of feature_angle_deg, in the order they are tried.
constexpr double kFeatureAngleFactors[] = {1.0, 0.75, 0.5};
constexpr int kRemeshRuns = 1 + static_cast<int>(std::size(kFeatureAngleFactors));

// Progress over the whole remesh, not over one run: up to kRemeshRuns runs (the plain one, then the
// feature-line ones) of up to max_attempts attempts each. Attempt a of run r reports r * max_attempts + a out
// of this total; the last unit is reported by remesh() as it returns, so the progress line never says 100%
// while a collapse, a Hausdorff distance or another run remains.
double remesh_progress_total(const RemeshOptions& o) {
  return static_cast<double>(kRemeshRuns) * o.max_attempts + 1;
}

// o for run `run` (0: the plain one): its reports placed in the whole remesh's count, its polls passed on.
RemeshOptions run_options(const RemeshOptions& o, int run) {
  RemeshOptions r = o;
  if (o.progress) {
    r.progress = [&o, run](const std::string& stage, double done, double) {
      if (stage.empty()) return o.progress("", 0, 0);
      o.progress(stage, static_cast<double>(run) * o.max_attempts + done, remesh_progress_total(o));
    };
  }
  return r;
}
}  // namespace

RemeshResult remesh(const Mesh& mesh, const RemeshOptions& o) {
  CSHAPES_REQUIRE(o.target_vertices >= 4, "remesh: target vertex count must be at least 4, got ",
                  o.target_vertices);
  CSHAPES_REQUIRE(o.tolerance > 0 && o.tolerance < 0.5, "remesh: tolerance must be in (0, 0.5), got ",
                  o.tolerance);
  // CGAL takes the iteration count as an unsigned: a negative one would never end.
  CSHAPES_REQUIRE(o.relaxation_iterations >= 1, "remesh: relaxation_iterations must be at least 1, got ",
                  o.relaxation_iterations);
  CSHAPES_REQUIRE(o.max_attempts >= 1, "remesh: max_attempts must be at least 1, got ", o.max_attempts);
  CSHAPES_REQUIRE(o.feature_angle_deg >= 0 && o.feature_angle_deg <= 180,
                  "remesh: feature_angle_deg must be in [0, 180], got ", o.feature_angle_deg);
  CSHAPES_REQUIRE(o.presimplify_factor >= 0, "remesh: presimplify_factor must be >= 0, got ",
                  o.presimplify_factor);
  require_memory(remesh_memory_bytes(o.target_vertices),
                 "remeshing to " + std::to_string(o.target_vertices) + " vertices");
  CSHAPES_REQUIRE(!mesh.is_point_cloud(),
                  "remesh: the input has no faces (a point cloud cannot be remeshed)");
  validate_mesh(mesh, "remesh input");
  // CGAL's predicates and the AABB tree overflow (1e100: SIGSEGV) or underflow (1e-100: SIGFPE) far from
  // unit size: the work is done at unit size, scaled by an exact power of two, and scaled back.
  const double scale = power_of_two_unit_scale(mesh.V);
  RemeshResult r = remesh_at_unit_size(scale == 1 ? mesh : Mesh{mesh.V * scale, mesh.F}, o);
  if (scale != 1) {
    r.mesh.V /= scale;
    r.target_edge_length /= scale;
    if (r.hausdorff >= 0) r.hausdorff /= scale;
  }
  if (o.progress) o.progress("remesh", remesh_progress_total(o), remesh_progress_total(o));
  return r;
}

namespace {

// The plain remesh and the first feature-line one (needed whenever the plain one misses the Hausdorff goal),
// computed at once on two threads when two are free and the memory allows: the results are those of one
// after the other (each run is serial and deterministic), in the wall time of the longer. Progress: the
// plain run reports, the other only polls, one call at a time; a failure is kept per run, and the plain
// run's is thrown first, the other's only where the sequence would have met it (the plain run missed the
// goal: featured_failure), or when it is the user's stop. False when not run side by side.
template <class Measured>
bool plain_and_featured_side_by_side(const RemeshOptions& o, const SurfaceMesh& input, const Measured& measured,
                                     RemeshResult& plain, std::optional<RemeshResult>& featured,
                                     std::exception_ptr& featured_failure) {
  const double room = available_memory_bytes();
  const double need = 2 * (remesh_memory_bytes(o.target_vertices) +
                           kRemeshBytesPerVertex * static_cast<double>(input.number_of_vertices()));
  if (omp_in_parallel() || omp_get_max_threads() < 2 || (room >= 0 && room < need)) return false;
  RemeshOptions reporting = o, polling = o;
  if (o.progress) {
    reporting.progress = [&o](const std::string& stage, double done, double total) {
      report_progress_in_parallel(o.progress, stage, done, total);
    };
    polling.progress = [&o](const std::string&, double, double) {
      report_progress_in_parallel(o.progress, "", 0, 0);
    };
  }
  std::exception_ptr plain_failure;
#pragma omp parallel sections num_threads(2)
  {
#pragma omp section
    try {
      plain = measured(reporting, 0);
    } catch (...) {
      plain_failure = std::current_exception();
    }
#pragma omp section
    try {
      featured = measured(polling, o.feature_angle_deg);
    } catch (...) {
      featured_failure = std::current_exception();
    }
  }
  if (plain_failure) std::rethrow_exception(plain_failure);
  // A stop heard by the other run only (its poll took the user's Ctrl-C) is the user's stop all the same.
  if (featured_failure) {
    try {
      std::rethrow_exception(featured_failure);
    } catch (const Cancelled&) {
      throw;
    } catch (...) {
    }
  }
  return true;
}

RemeshResult remesh_at_unit_size(const Mesh& mesh, const RemeshOptions& o) {
  SurfaceMesh input = cgal::to_surface_mesh(mesh, "remesh");
  // A much denser input (e.g. a marching-cubes surface) is first simplified by edge collapse to a few times
  // the target: isotropic remeshing would otherwise spend most of its time collapsing tiny edges, once per
  // attempt.
  if (o.presimplify_factor > 0 && static_cast<double>(input.number_of_vertices()) >
                                      o.presimplify_factor * static_cast<double>(o.target_vertices)) {
    // Shortest edge first, collapsed to its midpoint: several times cheaper than Lindstrom-Turk, and on a
    // surface this dense (edges far below the target length) the midpoints stay within a tiny distance of it.
    const Poller poller(o.progress);
    VertexCountStop stop{
        &input, static_cast<std::size_t>(o.presimplify_factor / 2 * static_cast<double>(o.target_vertices)),
        &poller};
    SMS::edge_collapse(input, stop,
                       CGAL::parameters::get_cost(SMS::Edge_length_cost<SurfaceMesh>())
                           .get_placement(SMS::Midpoint_placement<SurfaceMesh>()));
    input.collect_garbage();
  }
  // Without feature lines the triangles are best; keep the feature lines only when the shape needs them
  // (thin fins such as ears are otherwise cut back by about an edge length, beyond the Hausdorff goal).
  if (o.feature_angle_deg <= 0 || o.max_hausdorff_fraction <= 0)
    return remesh_once(input, mesh, run_options(o, 0), 0);
  const double goal = o.max_hausdorff_fraction * bbox_diagonal(mesh.V);
  auto measured = [&](const RemeshOptions& oo, double feature_angle_deg) {
    RemeshResult r = remesh_once(input, mesh, oo, feature_angle_deg);
    r.hausdorff = hausdorff_distance(mesh, r.mesh);
    if (feature_angle_deg > 0) r.feature_lines = true, r.feature_angle_deg = feature_angle_deg;
    return r;
  };
  RemeshResult plain;
  std::optional<RemeshResult> first_featured;
  std::exception_ptr featured_failure;
  const RemeshOptions plain_options = run_options(o, 0);
  if (!plain_and_featured_side_by_side(plain_options, input, measured, plain, first_featured, featured_failure))
    plain = measured(plain_options, 0);
  if (plain.hausdorff <= goal) return plain;
  if (featured_failure) std::rethrow_exception(featured_failure);
  // Ever more edges count as features (the angle threshold lowered in steps) until the goal is met; the
  // closest result is kept when it never is.
  RemeshResult best = plain;
  int run = 0;
  for (double factor : kFeatureAngleFactors) {
    ++run;  // runs 1 to kRemeshRuns - 1 of the progress count
    RemeshResult featured = factor == 1.0 && first_featured
                                ? std::move(*first_featured)
                                : measured(run_options(o, run), factor * o.feature_angle_deg);
    featured.attempts += best.attempts;
    if (featured.hausdorff < best.hausdorff) best = featured;
    if (best.hausdorff <= goal) break;
  }
  return best;
}

}  // namespace

double hausdorff_distance(const Mesh& a, const Mesh& b) {
  CSHAPES_REQUIRE(!a.is_point_cloud() && !b.is_point_cloud(), "hausdorff_distance: both inputs need faces");
  // The AABB tree's squared distances leave the double range far from unit size: measured at unit size.
  Points both(a.num_vertices() + b.num_vertices(), 3);
  both << a.V, b.V;
  const double scale = power_of_two_unit_scale(both);
  if (scale != 1) return hausdorff_distance(Mesh{a.V * scale, a.F}, Mesh{b.V * scale, b.F}) / scale;
  return std::max(one_sided_distance(a, SurfaceLocator(b.V, b.F)),
                  one_sided_distance(b, SurfaceLocator(a.V, a.F)));
}

AngleStats angle_stats(const Mesh& mesh) {
  AngleStats s;
  if (mesh.num_faces() == 0) return s;
  // Angles do not change with scale; the cross products' norms underflow or overflow far from unit size.
  const double scale = power_of_two_unit_scale(mesh.V);
  if (scale != 1) return angle_stats(Mesh{mesh.V * scale, mesh.F});
  constexpr double kDegrees = 180.0 / 3.14159265358979323846;
  s.min_angle = 180;
  double sum = 0;
  for (Index f = 0; f < mesh.num_faces(); ++f) {
    double face_min = 180;
    for (int c = 0; c < 3; ++c) {
      Eigen::Vector3d p = mesh.V.row(mesh.F(f, c));
      Eigen::Vector3d u = Eigen::Vector3d(mesh.V.row(mesh.F(f, (c + 1) % 3))) - p;
      Eigen::Vector3d w = Eigen::Vector3d(mesh.V.row(mesh.F(f, (c + 2) % 3))) - p;
      double angle = std::atan2(u.cross(w).norm(), u.dot(w)) * kDegrees;
      face_min = std::min(face_min, angle);
      s.max_angle = std::max(s.max_angle, angle);
    }
    s.min_angle = std::min(s.min_angle, face_min);
    sum += face_min;
  }
  s.mean_min_angle = sum / static_cast<double>(mesh.num_faces());
  return s;
}

bool self_intersects(const Mesh& mesh) {
  SurfaceMesh sm = cgal::to_surface_mesh(mesh, "remesh");
  return PMP::does_self_intersect(sm);
}

}  // namespace cshapes
