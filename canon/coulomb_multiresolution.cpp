#include "cshapes/canon/coulomb_multiresolution.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <vector>

#include "cshapes/support/format.h"
#include "cshapes/support/error.h"
#include "cshapes/mesh/point_kdtree.h"
#include "cshapes/mesh/locate_on_surface.h"
#include "cshapes/mesh/mesh.h"
#include "cshapes/mesh/remesh.h"
#include "cshapes/support/timing.h"

namespace cshapes {

namespace {


// The frame [b − a, c − a, n·scale] of a triangle, n its unit normal (zero for a degenerate one).
Eigen::Matrix3d triangle_frame(const Eigen::Vector3d& a, const Eigen::Vector3d& b, const Eigen::Vector3d& c,
                               double normal_scale) {
  Eigen::Matrix3d frame;
  const Eigen::Vector3d cross = (b - a).cross(c - a);
  const double norm = cross.norm();
  frame.col(0) = b - a;
  frame.col(1) = c - a;
  frame.col(2) = norm > 0 ? Eigen::Vector3d(cross / norm * normal_scale) : Eigen::Vector3d::Zero();
  return frame;
}

}  // namespace

Points prolong_to_fine(const Points& P, const Points& Vc, const Faces& Fc, const Points& Yc, const Points& N) {
  CSHAPES_REQUIRE(Vc.rows() == Yc.rows() && Fc.rows() > 0, "prolongation: ", Vc.rows(), " coarse vertices, ",
                  Yc.rows(), " form points, ", Fc.rows(), " faces");
  CSHAPES_REQUIRE(N.rows() == 0 || N.rows() == P.rows(), "prolongation: ", N.rows(), " normals for ", P.rows(),
                  " points");
  const Index nc = Vc.rows();
  std::vector<std::vector<int>> faces_of(nc);
  for (Index f = 0; f < Fc.rows(); ++f)
    for (int k = 0; k < 3; ++k) faces_of[Fc(f, k)].push_back(static_cast<int>(f));
  PointsKdAdaptor adaptor{Vc};
  PointsKdTree tree(3, adaptor, nanoflann::KDTreeSingleIndexAdaptorParams(10));
  const size_t neighbours = std::min<size_t>(N.rows() ? 16 : 8, static_cast<size_t>(nc));
  Points X(P.rows(), 3);
#pragma omp parallel
  {
    std::vector<uint32_t> found(neighbours);
    std::vector<double> squared(neighbours);
#pragma omp for schedule(static)
    for (Index i = 0; i < P.rows(); ++i) {
      const Eigen::Vector3d p = P.row(i).transpose();
      const double query[3] = {p[0], p[1], p[2]};
      const size_t count = tree.knnSearch(query, neighbours, found.data(), squared.data());
      // The closest triangle facing the point's way (normal · normal > 0), else the closest: where two parts
      // of the surface almost touch (a hand on a thigh), the closest coarse triangle may be the other part's,
      // whose normal faces the point's. Ranked by (facing away, distance).
      int best = -1, best_rank = 2;
      double best_distance = std::numeric_limits<double>::infinity();
      for (size_t k = 0; k < count; ++k)
        for (int f : faces_of[found[k]]) {
          const Eigen::Vector3d a = Vc.row(Fc(f, 0)), b = Vc.row(Fc(f, 1)), c = Vc.row(Fc(f, 2));
          const Eigen::Vector3d cross = (b - a).cross(c - a);
          if (cross.squaredNorm() == 0) continue;
          const int rank = N.rows() == 0 || cross.dot(N.row(i).transpose()) > 0 ? 0 : 1;
          if (rank > best_rank) continue;
          const double d = (closest_point_on_triangle(p, a, b, c) - p).squaredNorm();
          if (rank < best_rank || d < best_distance) {
            best_rank = rank;
            best_distance = d;
            best = f;
          }
        }
      if (best < 0) {  // only degenerate triangles near: follow the nearest vertex
        X.row(i) = Yc.row(found[0]) + (P.row(i) - Vc.row(found[0]));
        continue;
      }
      const int ia = Fc(best, 0), ib = Fc(best, 1), ic = Fc(best, 2);
      const Eigen::Vector3d a = Vc.row(ia), b = Vc.row(ib), c = Vc.row(ic);
      const Eigen::Vector3d a2 = Yc.row(ia), b2 = Yc.row(ib), c2 = Yc.row(ic);
      const double area = (b - a).cross(c - a).norm(), area2 = (b2 - a2).cross(c2 - a2).norm();
      const Eigen::Vector3d coords = triangle_frame(a, b, c, 1.0).colPivHouseholderQr().solve(p - a);
      const Eigen::Matrix3d frame2 = triangle_frame(a2, b2, c2, area > 0 ? std::sqrt(area2 / area) : 1.0);
      X.row(i) = (a2 + frame2 * coords).transpose();
    }
  }
  return X;
}

namespace {

// Projection sweeps only on the fine edges not torn (is_torn): they restore what the prolongation distorted
// locally (shear and uneven stretch within a coarse triangle, kinks across coarse edges) and leave the
// shape-wide form, the coarse one's, as it is (the averaged projection does not pull back a smooth dilation).
// Coulomb steps here would start the fine level's own inflation (the form came out more stretched than the
// coarse form: docs/coulomb-defaults.md, "The multiresolution switch"). Where a coarse gap crosses the fine
// mesh, edges the count did not tear stay stretched across it: after the sweeps, the kept edges still beyond
// the form quality's limit are torn too (by the same guard, into is_torn) and the sweeps repeated, up to
// tear_rounds times (the rounds after full_rounds with fewer sweeps, see there). The kept edges and their
// rest lengths of the last round are returned.
void refine(const Edges& E, const Eigen::VectorXd& rest, const CoulombCanonOptions& options, Points& X,
            std::vector<char>& is_torn, Edges& kept, Eigen::VectorXd& kept_rest,
            CoulombMultiresolutionResult& out) {
  const CoulombMultiresolutionOptions& mr = options.multiresolution;
  const Index n = X.rows();
  const double limit = FormQualityOptions{}.overstretch, mean_rest = rest.mean();
  for (int round = 0;; ++round) {
    std::vector<Index> kept_index;
    for (Index e = 0; e < E.rows(); ++e)
      if (!is_torn[e]) kept_index.push_back(e);
    kept.resize(static_cast<Index>(kept_index.size()), 2);
    kept_rest.resize(kept.rows());
    for (Index k = 0; k < kept.rows(); ++k) {
      kept.row(k) = E.row(kept_index[static_cast<size_t>(k)]);
      kept_rest[k] = rest[kept_index[static_cast<size_t>(k)]];
    }
    const MetricProjection projection(n, kept, kept_rest, options.projection);
    // Rounds beyond full_rounds run an eighth of the projections (a crack crossing a coarse gap grows by
    // about one fine edge per round, and a few sweeps carry the stretch to its tip), and the rest only when
    // nothing is overstretched after them, so that the form ends as relaxed as after a full round.
    const int iterations = round < mr.full_rounds || mr.refine_iterations == 0
                               ? mr.refine_iterations
                               : std::max(1, mr.refine_iterations / 8);
    for (int it = 0; it < iterations; ++it) projection.project(X);
    auto count_over = [&] {
      Index c = 0;
      for (Index k = 0; k < kept.rows(); ++k)
        c += (X.row(kept(k, 0)) - X.row(kept(k, 1))).norm() > limit * std::max(kept_rest[k], mean_rest);
      return c;
    };
    Index over = count_over();
    if (over == 0 && iterations < mr.refine_iterations) {
      for (int it = iterations; it < mr.refine_iterations; ++it) projection.project(X);
      over = count_over();
    }
    out.refine_rounds = round + 1;
    if (over == 0 || round >= mr.tear_rounds) break;
    const std::vector<Index> more = select_edges_to_tear(X, kept, kept_rest, n, over, options.tear_guard);
    if (more.empty()) break;  // the guard refuses every one: sweeps alone would change nothing
    out.extra_tears += static_cast<Index>(more.size());
    for (Index k : more) is_torn[kept_index[static_cast<size_t>(k)]] = 1;
  }
}

// The torn fine edges (rows of E) into the form's torn_edges and torn_vertices; returns a flag per edge of E.
std::vector<bool> record_torn_edges(const Edges& E, const std::vector<Index>& torn, Index n,
                                    CoulombCanonResult& fine) {
  std::vector<bool> torn_flags(E.rows(), false);
  Edges torn_edges(static_cast<Index>(torn.size()), 2);
  fine.torn_vertices = Eigen::VectorXd::Zero(n);
  for (size_t k = 0; k < torn.size(); ++k) {
    torn_flags[torn[k]] = true;
    torn_edges.row(static_cast<Index>(k)) = E.row(torn[k]);
    fine.torn_vertices(E(torn[k], 0)) = 1;
    fine.torn_vertices(E(torn[k], 1)) = 1;
  }
  fine.torn_edges = std::move(torn_edges);
  return torn_flags;
}

std::string multiresolution_note(const CoulombMultiresolutionResult& out, Index n, size_t fine_torn,
                                 int refine_iterations) {
  return "multiresolution: " + std::to_string(n) + " vertices through " + std::to_string(out.coarse_vertices) +
         " (remesh " + significant(out.remesh_seconds) + " s, coarse " + std::to_string(out.coarse_iterations) +
         " iterations " + significant(out.coarse_seconds) + " s, " + std::to_string(out.coarse_torn_edges) +
         " coarse edges torn -> " + std::to_string(fine_torn) + " fine (" + std::to_string(out.extra_tears) +
         " of them overstretched after the sweeps), " + std::to_string(refine_iterations) +
         " fine projections × " + std::to_string(out.refine_rounds) + " rounds " +
         significant(out.refine_seconds) + " s)";
}

}  // namespace

CoulombMultiresolutionResult coulomb_multiresolution(const Mesh& mesh, const CoulombCanonOptions& options) {
  const CoulombMultiresolutionOptions& mr = options.multiresolution;
  const Index n = mesh.num_vertices();
  CoulombMultiresolutionResult out;
  auto single_level = [&](const std::string& why) {
    out.result = coulomb_canonical_form(mesh.V, mesh_edges(mesh.F), options);
    out.note = "single level (" + why + ")";
    return out;
  };
  check_limit(coulomb_limits::kMultiresolutionAbove, static_cast<double>(mr.above_resolution), "coulomb");
  check_limit(coulomb_limits::kCoarseVertices, static_cast<double>(mr.coarse_vertices), "coulomb");
  check_limit(coulomb_limits::kTearRounds, mr.tear_rounds, "coulomb");
  CSHAPES_REQUIRE(mr.full_rounds >= 0, "coulomb multiresolution: full_rounds must be ≥ 0, not ",
                  mr.full_rounds);
  CSHAPES_REQUIRE(mr.refine_iterations >= 0, "coulomb multiresolution: refine_iterations must be ≥ 0, not ",
                  mr.refine_iterations);
  if (mr.above_resolution == 0) return single_level("multiresolution off");
  if (mesh.is_point_cloud()) return single_level("a point cloud has no surface to coarsen");
  const double resolution = even_triangulation_vertices(mesh.V, mesh.F);
  if (resolution <= static_cast<double>(mr.above_resolution))
    return single_level(std::to_string(n) + " vertices, resolution " + std::to_string(std::lround(resolution)) +
                        " = area / (√3/2 · mean edge²); at most " + std::to_string(mr.above_resolution));
  if (mr.coarse_vertices >= n)
    return single_level(std::to_string(n) + " vertices, not more than the coarse version's " +
                        std::to_string(mr.coarse_vertices));

  auto start = WallClock::now();
  RemeshOptions ro;
  ro.target_vertices = mr.coarse_vertices;
  ro.tolerance = 0.02;
  ro.progress = polls_of(options.progress);  // a stop is heard during the remesh; its reports are not the form's
  Mesh coarse;
  try {
    coarse = remesh(mesh, ro).mesh;
  } catch (const Error& error) {
    return single_level(std::string("the remesher refused the mesh: ") + error.what());
  }
  out.remesh_seconds = seconds_since(start);

  start = WallClock::now();
  CoulombCanonOptions coarse_options = options;
  coarse_options.progress = polls_of(options.progress);
  const CoulombCanonResult coarse_form =
      coulomb_canonical_form(coarse.V, mesh_edges(coarse.F), coarse_options);
  out.coarse_seconds = seconds_since(start);
  out.coarse_vertices = coarse.num_vertices();
  out.coarse_iterations = coarse_form.iterations;
  out.coarse_torn_edges = coarse_form.torn_edges.rows();

  start = WallClock::now();
  const Points X = prolong_to_fine(mesh.V, coarse.V, coarse.F, coarse_form.X,
                                   mr.facing_triangles ? vertex_normals(mesh) : Points());
  const Edges E = mesh_edges(mesh.F);
  const Eigen::VectorXd rest = edge_lengths(mesh.V, E);
  // As many fine edges torn as keep the cut's length: a cut across the surface crosses ∝ 1/h edges.
  const double coarse_edge = edge_lengths(coarse.V, mesh_edges(coarse.F)).mean();
  const Index fine_tears = static_cast<Index>(
      std::lround(static_cast<double>(out.coarse_torn_edges) * coarse_edge / std::max(rest.mean(), 1e-300)));
  std::vector<char> is_torn(E.rows(), 0);
  for (Index e : select_edges_to_tear(X, E, rest, n, fine_tears, options.tear_guard)) is_torn[e] = 1;
  out.prolong_seconds = seconds_since(start);

  start = WallClock::now();
  CoulombCanonResult fine;
  fine.X = X;
  Edges kept;
  Eigen::VectorXd kept_rest;
  refine(E, rest, options, fine.X, is_torn, kept, kept_rest, out);
  std::vector<Index> torn;
  for (Index e = 0; e < E.rows(); ++e)
    if (is_torn[e]) torn.push_back(e);
  CSHAPES_REQUIRE(fine.X.allFinite(), "coulomb multiresolution: non-finite coordinates after the refinement");
  out.refine_seconds = seconds_since(start);
  const std::vector<bool> torn_flags = record_torn_edges(E, torn, n, fine);
  fine.quality = form_quality(mesh.V, E, fine.X, &torn_flags);
  fine.not_converged = coarse_form.not_converged.empty() ? "" : coarse_form.not_converged + " (coarse)";
  if (!fine.not_converged.empty()) fail_form_quality(fine.quality, fine.not_converged);
  fine.violation = metric_violation(fine.X, kept, kept_rest);
  CoulombOptions final_energy = options.energy;
  final_energy.accuracy = std::min(options.energy.accuracy, options.result_accuracy);
  fine.energy = coulomb_energy_gradient(fine.X, final_energy).energy;
  fine.edges = kept;
  fine.rest_lengths = kept_rest;
  fine.history = coarse_form.history;
  fine.start = coarse_form.start + " (on the coarse mesh)";
  if (!coarse_form.flatten_plane.empty())
    fine.flatten_plane = coarse_form.flatten_plane + " (on the coarse mesh)";
  fine.iterations = coarse_form.iterations;
  fine.converged = coarse_form.converged;
  fine.stop_reason = coarse_form.stop_reason + " (coarse), then " + std::to_string(mr.refine_iterations) +
                     " fine projections" +
                     (out.refine_rounds > 1 ? " in each of " + std::to_string(out.refine_rounds) + " rounds" : "");
  fine.seconds = out.remesh_seconds + out.coarse_seconds + out.prolong_seconds + out.refine_seconds;
  out.result = std::move(fine);
  out.used = true;
  out.note = multiresolution_note(out, n, torn.size(), mr.refine_iterations);
  return out;
}

}  // namespace cshapes
