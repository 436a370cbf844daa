#include "cshapes/experiments/bench_geodesics.h"

#include <omp.h>

#include <algorithm>
#include <cmath>
#include <numeric>
#include <random>

#include "cshapes/support/error.h"
#include "cshapes/geodesics/fast_marching.h"
#include "cshapes/geodesics/geodesics.h"
#include "cshapes/geodesics/heat_method.h"
#include "cshapes/mesh/io.h"
#include "cshapes/mesh/subdivide.h"
#include "cshapes/data/synthetic.h"
#include "cshapes/support/timing.h"
#include "cshapes/experiments/bench_support.h"

namespace cshapes {

namespace {

Mesh refine_to(Mesh mesh, Index target, std::string& description) {
  RefineToVertexCountResult refined = refine_to_vertex_count(std::move(mesh), target);
  description += ", " + std::to_string(refined.subdivisions) + "× 1-to-4 midpoint subdivision, then " +
                 std::to_string(refined.edge_splits) + " longest-edge splits";
  return std::move(refined.mesh);
}

Mesh benchmark_mesh(const GeodesicsBenchOptions& options, std::string& description) {
  CSHAPES_REQUIRE((options.n > 0) != !options.mesh.empty(),
                  "give exactly one of --vertices N (a torus) and --mesh FILE");
  if (options.n > 0) {
    // A torus (R = 2, r = 0.7) with a near-square grid, then refined to exactly n vertices.
    const int nv = std::max(3, static_cast<int>(std::sqrt(options.n / 2.86)));
    const int nu = std::max(3, options.n / nv);
    Mesh mesh = torus(nu, nv, 2.0, 0.7);
    description = "torus " + std::to_string(nu) + "x" + std::to_string(nv) + " (R 2, r 0.7)";
    if (mesh.num_vertices() < options.n) mesh = refine_to(std::move(mesh), options.n, description);
    return mesh;
  }
  Mesh mesh = read_mesh(options.mesh);
  description = options.mesh;
  if (options.vertices > 0) {
    CSHAPES_REQUIRE(options.vertices >= mesh.num_vertices(), "--vertices ", options.vertices,
                    " is below the mesh's ", mesh.num_vertices(), " (only refinement is available)");
    mesh = refine_to(std::move(mesh), options.vertices, description);
  }
  return mesh;
}

double mean_relative_error(const Eigen::VectorXd& d, const Eigen::VectorXd& exact, double min_distance) {
  double sum = 0;
  Index count = 0;
  for (Index i = 0; i < d.size(); ++i)
    if (exact[i] > min_distance) sum += std::abs(d[i] - exact[i]) / exact[i], ++count;
  return count ? sum / count : 0.0;
}

double mean(const std::vector<double>& v) {
  return std::accumulate(v.begin(), v.end(), 0.0) / v.size();
}

// The anchor: CGAL Heat_method_3, one solver per thread, one source at a time over `sources`; set-up once (one
// factorisation per thread, concurrently), then all n sources at the sampled rate.
void time_cgal_anchor(const Mesh& mesh, CgalHeatMode mode, const std::vector<int>& sources, int threads,
                      GeodesicsBenchResult& result) {
  double setup_wall = 0, setup_cpu = 0, loop_wall = 0, loop_cpu = 0;
  {
    Stopwatch setup_clock, loop_clock;
#pragma omp parallel num_threads(threads)
    {
      CgalHeatMethod solver(mesh, mode);
#pragma omp barrier
#pragma omp single
      {
        setup_wall = setup_clock.wall_seconds();
        setup_cpu = setup_clock.cpu_seconds();
        loop_clock.restart();
      }
#pragma omp for schedule(dynamic, 1)
      for (size_t k = 0; k < sources.size(); ++k) solver.distances({sources[k]});
#pragma omp single
      {
        loop_wall = loop_clock.wall_seconds();
        loop_cpu = loop_clock.cpu_seconds();
      }
    }
  }
  const Index n = mesh.num_vertices();
  const double scale = static_cast<double>(n) / sources.size();
  result.anchor.method =
      "CGAL Heat_method_3 (" + to_string(mode) + "), one source at a time, one solver per thread";
  result.anchor.seconds = setup_wall + loop_wall * scale;
  result.anchor.cpu_seconds = setup_cpu + loop_cpu * scale;
  result.anchor.sampled_sources = sources.size();
  result.anchor_extrapolated = sources.size() < static_cast<size_t>(n);
  result.anchor_setup_seconds = setup_wall;
  result.anchor_seconds_per_source_per_thread = loop_wall * threads / sources.size();
}

// Accuracy against exact geodesics on result.exact_sources (vertices farther than 3 mean edge lengths h): our
// matrix D, the anchor and fast marching.
void measure_accuracy(const Mesh& mesh, CgalHeatMode mode, const DistanceMatrix& D, const FastMarching& fmm,
                      double h, GeodesicsBenchResult& result) {
  const std::vector<int>& exact_sources = result.exact_sources;
  std::vector<double> err_ours(exact_sources.size()), err_anchor(exact_sources.size()),
      err_fmm(exact_sources.size());
  const Stopwatch exact_clock;
#pragma omp parallel for schedule(dynamic, 1)
  for (size_t k = 0; k < exact_sources.size(); ++k) {
    const int s = exact_sources[k];
    Eigen::VectorXd exact = exact_geodesics(mesh, {s});
    err_ours[k] = mean_relative_error(D.col(s).cast<double>(), exact, 3 * h);
    err_anchor[k] = mean_relative_error(cgal_heat_method(mesh, {s}, mode), exact, 3 * h);
    err_fmm[k] = mean_relative_error(fmm.distances({s}), exact, 3 * h);
  }
  result.exact_seconds = exact_clock.wall_seconds();
  result.ours.mean_relative_error = mean(err_ours);
  result.anchor.mean_relative_error = mean(err_anchor);
  result.fmm.mean_relative_error = mean(err_fmm);
}

}  // namespace

GeodesicsBenchResult bench_geodesics(const GeodesicsBenchOptions& options) {
  GeodesicsBenchResult result;
  result.options = options;
  const CgalHeatMode mode = options.heat_mode;
  const Mesh mesh = benchmark_mesh(options, result.mesh);
  const Index n = mesh.num_vertices();
  const int threads = omp_get_max_threads();
  result.vertices = n;
  result.faces = mesh.num_faces();
  result.threads = threads;
  options.notes.say("bench geodesics: " + result.mesh + ": " + std::to_string(n) + " vertices, " +
                    std::to_string(threads) + " threads");
  const double h = edge_lengths(mesh.V, mesh_edges(mesh.F)).mean();
  std::mt19937 rng(options.seed);
  auto sample = [&](int count) {
    std::vector<int> all(n);
    std::iota(all.begin(), all.end(), 0);
    std::shuffle(all.begin(), all.end(), rng);
    all.resize(std::min<Index>(count, n));
    return all;
  };

  // Ours: the full all-pairs matrix, as `cshapes geodesics --method heat` computes it.
  GeodesicOptions ours_options;
  ours_options.method = GeodesicMethod::Heat;
  ours_options.heat_mode = mode;
  ours_options.progress = options.notes.progress;
  const Stopwatch ours_clock;
  const DistanceMatrix D = all_pairs_geodesics(mesh, ours_options);
  result.ours.method = "heat (ours): factorised once with " + HeatMethod::backend() +
                       ", blocks of right-hand sides, OpenMP over blocks; symmetrised";
  result.ours.seconds = ours_clock.wall_seconds();
  result.ours.cpu_seconds = ours_clock.cpu_seconds();

  time_cgal_anchor(mesh, mode, sample(options.anchor_samples), threads, result);

  // Fast marching on a sample, extrapolated the same way (its set-up is the stencil precomputation).
  const std::vector<int> fmm_sources = sample(options.fmm_samples);
  const Stopwatch fmm_clock;
  FastMarching fmm(mesh);
  const double fmm_setup = fmm_clock.wall_seconds();
  const Stopwatch fmm_loop;
#pragma omp parallel for schedule(dynamic, 4)
  for (size_t k = 0; k < fmm_sources.size(); ++k) fmm.distances({fmm_sources[k]});
  result.fmm.method = "fast marching (ours, Kimmel-Sethian with unfolding), extrapolated from a sample";
  result.fmm.seconds = fmm_setup + fmm_loop.wall_seconds() * n / fmm_sources.size();
  result.fmm.sampled_sources = fmm_sources.size();

  result.exact_sources = sample(options.exact_samples);
  measure_accuracy(mesh, mode, D, fmm, h, result);
  if (n == 3505) result.paper_seconds = 10.24;
  if (n == 22738) result.paper_seconds = 647.6;
  return result;
}

nlohmann::json to_json(const GeodesicsBenchResult& r) {
  nlohmann::json out = {
      {"benchmark", "all-pairs geodesics"},
      {"mesh", r.mesh},
      {"vertices", r.vertices},
      {"faces", r.faces},
      {"threads", r.threads},
      {"heat_mode", to_string(r.options.heat_mode)},
      {"ours",
       {{"method", r.ours.method},
        {"seconds", r.ours.seconds},
        {"cpu_seconds", r.ours.cpu_seconds},
        {"mean_relative_error_vs_exact", r.ours.mean_relative_error}}},
      {"anchor",
       {{"method", r.anchor.method},
        {"seconds", r.anchor.seconds},
        {"cpu_seconds", r.anchor.cpu_seconds},
        {"extrapolated", r.anchor_extrapolated},
        {"sampled_sources", r.anchor.sampled_sources},
        {"setup_seconds", r.anchor_setup_seconds},
        {"seconds_per_source_per_thread", r.anchor_seconds_per_source_per_thread},
        {"mean_relative_error_vs_exact", r.anchor.mean_relative_error}}},
      {"fmm",
       {{"method", r.fmm.method},
        {"seconds", r.fmm.seconds},
        {"sampled_sources", r.fmm.sampled_sources},
        {"mean_relative_error_vs_exact", r.fmm.mean_relative_error}}},
      {"speedup_vs_anchor", r.speedup_vs_anchor()},
      {"cpu_speedup_vs_anchor", r.cpu_speedup_vs_anchor()},
      {"exact_sources", r.exact_sources},
      {"exact_seconds", r.exact_seconds},
      {"error_measure", "mean |d - exact| / exact over vertices farther than 3 mean edge lengths"},
  };
  if (r.anchor_extrapolated)
    out["anchor"]["note"] = "timed on " + std::to_string(r.anchor.sampled_sources) +
                            " random sources and extrapolated to n: set-up + n × seconds per source";
  if (r.paper_seconds > 0) out["paper_seconds"] = r.paper_seconds;
  out["build"] = build_json();
  return out;
}

}  // namespace cshapes
