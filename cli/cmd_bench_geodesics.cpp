// cshapes bench geodesics (--n N | --mesh FILE [--vertices N]) --json: all-pairs geodesic distances by our
// block heat method against the anchor, CGAL's Heat_method_3 solving one source at a time (the paper's
// baseline: 10.24 s at 3,505 vertices, 647.6 s at 22,738), with both methods' mean relative error against
// CGAL's exact geodesics on sampled sources. Fast marching is timed on the same sample and reported beside.
//
// Both sides run on the same threads: ours parallel over blocks of sources, the anchor with one CGAL solver
// per thread. The anchor is timed on --anchor-samples random sources (all n when that many are asked for) and
// extrapolated to n (set-up + n × seconds per source); the JSON says so.
// Wall-clock and CPU seconds are both reported: on a shared machine the CPU-time ratio is the steadier one.
#include <omp.h>

#include <algorithm>
#include <cmath>
#include <iostream>
#include <map>
#include <numeric>
#include <random>

#include "core/error.h"
#include "core/fast_marching.h"
#include "core/geodesics.h"
#include "core/heat_method.h"
#include "core/subdivide.h"
#include "core/synthetic.h"
#include "core/timing.h"
#include "cli/command.h"

namespace cshapes::cli {
namespace {

struct BenchArgs {
  int n = 0;
  std::string mesh_path;
  int vertices = 0;
  std::string heat_mode = "idt";
  int anchor_samples = 96;
  int exact_samples = 4;
  int fmm_samples = 256;
  unsigned seed = 1;
  bool json = false;
} args;

Mesh refine_to(Mesh mesh, Index target, std::string& description) {
  RefineToVertexCountResult refined = refine_to_vertex_count(std::move(mesh), target);
  description += ", " + std::to_string(refined.subdivisions) + "× 1-to-4 midpoint subdivision, then " +
                 std::to_string(refined.edge_splits) + " longest-edge splits";
  return std::move(refined.mesh);
}

double mean_relative_error(const Eigen::VectorXd& d, const Eigen::VectorXd& exact, double min_distance) {
  double sum = 0;
  Index count = 0;
  for (Index i = 0; i < d.size(); ++i)
    if (exact[i] > min_distance) sum += std::abs(d[i] - exact[i]) / exact[i], ++count;
  return count ? sum / count : 0.0;
}

int run() {
  CSHAPES_REQUIRE((args.n > 0) != !args.mesh_path.empty(), "give exactly one of --n N and --mesh FILE");
  const CgalHeatMode mode = parse_cgal_heat_mode(args.heat_mode);
  std::string description;
  Mesh mesh;
  if (args.n > 0) {
    // A torus (R = 2, r = 0.7) with a near-square grid, then refined to exactly n vertices.
    const int nv = std::max(3, static_cast<int>(std::sqrt(args.n / 2.86)));
    const int nu = std::max(3, args.n / nv);
    mesh = torus(nu, nv, 2.0, 0.7);
    description = "torus " + std::to_string(nu) + "x" + std::to_string(nv) + " (R 2, r 0.7)";
    if (mesh.num_vertices() < args.n) mesh = refine_to(std::move(mesh), args.n, description);
  } else {
    mesh = read_mesh(args.mesh_path);
    description = args.mesh_path;
    if (args.vertices > 0) {
      CSHAPES_REQUIRE(args.vertices >= mesh.num_vertices(), "--vertices ", args.vertices,
                      " is below the mesh's ", mesh.num_vertices(), " (only refinement is available)");
      mesh = refine_to(std::move(mesh), args.vertices, description);
    }
  }
  const Index n = mesh.num_vertices();
  const int threads = omp_get_max_threads();
  note("bench geodesics: " + description + ": " + std::to_string(n) + " vertices, " +
       std::to_string(threads) + " threads");
  const double h = edge_lengths(mesh.V, mesh_edges(mesh.F)).mean();
  std::mt19937 rng(args.seed);
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
  ours_options.progress = progress_printer();
  Stopwatch ours_clock;
  DistanceMatrix D = all_pairs_geodesics(mesh, ours_options);
  const double ours_wall = ours_clock.wall_seconds(), ours_cpu = ours_clock.cpu_seconds();

  // Anchor: CGAL Heat_method_3, one solver per thread, one source at a time.
  std::vector<int> anchor_sources = sample(args.anchor_samples);
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
      for (size_t k = 0; k < anchor_sources.size(); ++k) solver.distances({anchor_sources[k]});
#pragma omp single
      {
        loop_wall = loop_clock.wall_seconds();
        loop_cpu = loop_clock.cpu_seconds();
      }
    }
  }
  // Set-up once (one factorisation per thread, concurrently), then n sources at the sampled rate.
  const double scale = static_cast<double>(n) / anchor_sources.size();
  const double anchor_wall = setup_wall + loop_wall * scale;
  const double anchor_cpu = setup_cpu + loop_cpu * scale;
  const bool extrapolated = anchor_sources.size() < static_cast<size_t>(n);

  // Fast marching on a sample, extrapolated the same way (its set-up is the stencil precomputation).
  std::vector<int> fmm_sources = sample(args.fmm_samples);
  Stopwatch fmm_clock;
  FastMarching fmm(mesh);
  const double fmm_setup = fmm_clock.wall_seconds();
  Stopwatch fmm_loop;
#pragma omp parallel for schedule(dynamic, 4)
  for (size_t k = 0; k < fmm_sources.size(); ++k) fmm.distances({fmm_sources[k]});
  const double fmm_wall = fmm_setup + fmm_loop.wall_seconds() * n / fmm_sources.size();

  // Accuracy against exact geodesics on sampled sources (vertices farther than 3 mean edge lengths).
  std::vector<int> exact_sources = sample(args.exact_samples);
  std::vector<double> err_ours(exact_sources.size()), err_anchor(exact_sources.size()),
      err_fmm(exact_sources.size());
  Stopwatch exact_clock;
#pragma omp parallel for schedule(dynamic, 1)
  for (size_t k = 0; k < exact_sources.size(); ++k) {
    const int s = exact_sources[k];
    Eigen::VectorXd exact = exact_geodesics(mesh, {s});
    err_ours[k] = mean_relative_error(D.col(s).cast<double>(), exact, 3 * h);
    err_anchor[k] = mean_relative_error(cgal_heat_method(mesh, {s}, mode), exact, 3 * h);
    err_fmm[k] = mean_relative_error(fmm.distances({s}), exact, 3 * h);
  }
  const double exact_wall = exact_clock.wall_seconds();
  auto mean = [](const std::vector<double>& v) {
    return std::accumulate(v.begin(), v.end(), 0.0) / v.size();
  };

  std::map<Index, double> paper = {{3505, 10.24}, {22738, 647.6}};
  nlohmann::json out = {
      {"benchmark", "all-pairs geodesics"},
      {"mesh", description},
      {"vertices", n},
      {"faces", mesh.num_faces()},
      {"threads", threads},
      {"heat_mode", to_string(mode)},
      {"ours",
       {{"method", "heat (ours): factorised once with " + HeatMethod::backend() +
                       ", blocks of right-hand sides, OpenMP over blocks; symmetrised"},
        {"seconds", ours_wall},
        {"cpu_seconds", ours_cpu},
        {"mean_relative_error_vs_exact", mean(err_ours)}}},
      {"anchor",
       {{"method",
         "CGAL Heat_method_3 (" + to_string(mode) + "), one source at a time, one solver per thread"},
        {"seconds", anchor_wall},
        {"cpu_seconds", anchor_cpu},
        {"extrapolated", extrapolated},
        {"sampled_sources", anchor_sources.size()},
        {"setup_seconds", setup_wall},
        {"seconds_per_source_per_thread", loop_wall * threads / anchor_sources.size()},
        {"mean_relative_error_vs_exact", mean(err_anchor)}}},
      {"fmm",
       {{"method", "fast marching (ours, Kimmel-Sethian with unfolding), extrapolated from a sample"},
        {"seconds", fmm_wall},
        {"sampled_sources", fmm_sources.size()},
        {"mean_relative_error_vs_exact", mean(err_fmm)}}},
      {"speedup_vs_anchor", anchor_wall / ours_wall},
      {"cpu_speedup_vs_anchor", anchor_cpu / ours_cpu},
      {"exact_sources", exact_sources},
      {"exact_seconds", exact_wall},
      {"error_measure", "mean |d - exact| / exact over vertices farther than 3 mean edge lengths"},
  };
  if (extrapolated)
    out["anchor"]["note"] = "timed on " + std::to_string(anchor_sources.size()) +
                            " random sources and extrapolated to n: set-up + n × seconds per source";
  if (paper.count(n)) out["paper_seconds"] = paper[n];
  if (args.json)
    std::cout << out.dump(2) << std::endl;
  else
    std::cout << "ours " << ours_wall << " s, anchor " << anchor_wall << " s"
              << (extrapolated ? " (extrapolated)" : "") << ", speedup " << anchor_wall / ours_wall
              << "; mean relative error ours " << mean(err_ours) << ", anchor " << mean(err_anchor)
              << ", fmm " << mean(err_fmm) << std::endl;
  return 0;
}

const bool registered = register_command(
    {{"bench", "geodesics"},
     "All-pairs geodesics: our block heat method vs CGAL's Heat_method_3 one source at a time, errors vs "
     "exact",
     [](CLI::App& app) {
       app.add_option("--n", args.n, "generate a torus refined to exactly N vertices");
       app.add_option("--mesh", args.mesh_path, "benchmark this mesh");
       app.add_option(
           "--vertices", args.vertices,
           "refine --mesh to exactly this many vertices (1-to-4 subdivision, then longest-edge splits)");
       app.add_option("--heat-mode", args.heat_mode, "idt or direct, for both heat methods")
           ->capture_default_str()
           ->check(one_of({"idt", "direct"}));
       app.add_option("--anchor-samples", args.anchor_samples,
                      "sources timed for CGAL's heat method (n: the full all-pairs run)")
           ->capture_default_str();
       app.add_option("--exact-samples", args.exact_samples, "sources with exact geodesics for the errors")
           ->capture_default_str();
       app.add_option("--fmm-samples", args.fmm_samples, "sources timed for fast marching")
           ->capture_default_str();
       app.add_option("--seed", args.seed, "random seed for the sampled sources")->capture_default_str();
       app.add_flag("--json", args.json, "print JSON");
     },
     run});

}  // namespace
}  // namespace cshapes::cli
