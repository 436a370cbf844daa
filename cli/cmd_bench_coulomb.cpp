// cshapes bench coulomb: seconds per Coulomb gradient, fast (FMM) vs direct summation, and the fast method's
// relative error against direct summation, measured in one run.
//
//   cshapes bench coulomb --n 100000 --distribution uniform --json
//   cshapes bench coulomb --mesh ../shared/data/tosca5k/cat0.off --json            (the mesh's vertices)
//   cshapes bench coulomb --mesh ../shared/data/tosca5k/cat0.off --n 100000 --json (n points on its surface)
//
// Up to --full-direct-max points the direct sum is complete (timed as the median of --repeats runs) and the
// errors are over all points; above it the exact sum runs on a random sample of --sample targets, the
// errors are over those targets (energy error from their potentials), and direct_seconds is the sample's
// time scaled by n/sample (direct_extrapolated = true).
#include <omp.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <iostream>
#include <numeric>
#include <random>

#include "canon/coulomb_energy.h"
#include "canon/coulomb_fmm.h"
#include "core/error.h"
#include "core/io.h"
#include "core/synthetic.h"
#include "core/timing.h"
#include "cli/command.h"

namespace cshapes::cli {
namespace {

struct BenchArgs {
  Index n = 0;
  std::string distribution = "uniform";
  std::string mesh;
  int repeats = 5;
  double accuracy = 1e-3;
  int order = 0;
  double opening_angle = 0;
  int leaf_size = 0;
  Index sample = 1000;
  Index full_direct_max = 50000;
  unsigned seed = 1;
  bool json = false;
} args;

// Median wall-clock seconds over the runs (core/timing.h's median); cpu_seconds (if given) gets the median
// process CPU seconds, which on a machine shared with other jobs shows the work done independently of the
// share of the cores obtained.
template <class F>
double median_seconds(int repeats, F&& f, double* cpu_seconds = nullptr) {
  std::vector<double> wall, cpu;
  for (int r = 0; r < repeats; ++r) {
    const Stopwatch stopwatch;
    f();
    wall.push_back(stopwatch.wall_seconds());
    cpu.push_back(stopwatch.cpu_seconds());
  }
  if (cpu_seconds) *cpu_seconds = median(cpu);
  return median(wall);
}

int run() {
  std::mt19937_64 rng(args.seed);
  Points X;
  std::string distribution = args.distribution;
  if (!args.mesh.empty()) {
    const Mesh mesh = read_mesh(args.mesh);
    if (args.n <= 0 || args.n == mesh.V.rows()) {
      X = mesh.V;
      distribution = "mesh-vertices:" + args.mesh;
    } else {
      CSHAPES_REQUIRE(mesh.F.rows() > 0, "bench coulomb: ", args.mesh, " has no faces to sample points on");
      X = sample_surface(mesh, args.n, rng);
      distribution = "mesh-surface:" + args.mesh;
    }
  } else {
    CSHAPES_REQUIRE(args.n >= 2, "bench coulomb: --n must be at least 2 (or give --mesh)");
    X = random_points(args.n, parse_point_distribution(args.distribution), rng);
  }
  const Index n = X.rows();

  CoulombFmmOptions fmm_options;
  fmm_options.accuracy = args.accuracy;
  fmm_options.order = args.order;
  fmm_options.opening_angle = args.opening_angle;
  fmm_options.leaf_size = args.leaf_size;
  fmm_options.want_potentials = true;
  CoulombFmmStats stats;
  CoulombEvaluation fast;
  double fast_cpu_seconds = 0;
  const double fast_seconds = median_seconds(
      args.repeats, [&] { fast = coulomb_fmm(X, fmm_options, &stats); }, &fast_cpu_seconds);

  const bool full = n <= args.full_direct_max;
  double direct_cpu_seconds = 0, direct_float_cpu_seconds = 0, direct_seconds = 0, direct_float_seconds = 0,
         gradient_error = 0, energy_error = 0;
  Index error_targets = n;
  if (full) {
    CoulombEvaluation direct;
    direct_seconds = median_seconds(
        args.repeats, [&] { direct = coulomb_direct(X); }, &direct_cpu_seconds);
    direct_float_seconds = median_seconds(
        args.repeats, [&] { coulomb_direct_float(X); }, &direct_float_cpu_seconds);
    const CoulombErrors errors = coulomb_errors(fast, direct);
    gradient_error = errors.gradient;
    energy_error = errors.energy;
  } else {
    error_targets = std::min(args.sample, n);
    std::vector<Index> all(n);
    std::iota(all.begin(), all.end(), Index(0));
    for (Index t = 0; t < error_targets; ++t)  // partial Fisher–Yates: distinct random targets
      std::swap(all[t], all[t + std::uniform_int_distribution<Index>(0, n - 1 - t)(rng)]);
    std::vector<Index> targets(all.begin(), all.begin() + error_targets);
    CoulombTargetSums exact;
    const double sample_seconds = median_seconds(
        1, [&] { exact = coulomb_direct_targets(X, targets); }, &direct_cpu_seconds);
    direct_seconds = sample_seconds * double(n) / double(error_targets);
    direct_cpu_seconds *= double(n) / double(error_targets);
    const CoulombErrors errors = coulomb_errors(fast, targets, exact);
    gradient_error = errors.gradient;
    energy_error = errors.energy;
  }

  nlohmann::json j = {{"n", n},
                      {"distribution", distribution},
                      {"direct_seconds", direct_seconds},
                      {"direct_extrapolated", !full},
                      {"fast_seconds", fast_seconds},
                      {"direct_cpu_seconds", direct_cpu_seconds},
                      {"fast_cpu_seconds", fast_cpu_seconds},
                      {"speedup", direct_seconds / fast_seconds},
                      {"gradient_rel_error", gradient_error},
                      {"energy_rel_error", energy_error},
                      {"error_targets", error_targets},
                      {"threads", omp_get_max_threads()},
                      {"accuracy", args.accuracy},
                      {"order", stats.order},
                      {"opening_angle", stats.opening_angle},
                      {"leaf_size", stats.leaf_size},
                      {"repeats", args.repeats},
                      {"cells", stats.cells},
                      {"m2l_interactions", stats.m2l_interactions},
                      {"p2p_interactions", stats.p2p_interactions},
                      {"fast_phase_seconds",
                       {{"tree", stats.seconds_tree},
                        {"upward", stats.seconds_upward},
                        {"traversal", stats.seconds_traversal},
                        {"interactions", stats.seconds_interactions},
                        {"m2l_thread_seconds", stats.seconds_m2l},
                        {"p2p_thread_seconds", stats.seconds_p2p},
                        {"downward", stats.seconds_downward}}}};
  if (full) {
    j["direct_float_seconds"] = direct_float_seconds;
    j["direct_float_cpu_seconds"] = direct_float_cpu_seconds;
    j["speedup_vs_direct_float"] = direct_float_seconds / fast_seconds;
  }
  if (args.json) {
    std::cout << j.dump(2) << std::endl;
  } else {
    std::printf("n %ld (%s), %d threads\n", static_cast<long>(n), distribution.c_str(),
                omp_get_max_threads());
    std::printf("  direct  %.4g s%s\n", direct_seconds, full ? "" : " (extrapolated from the sample)");
    if (full) std::printf("  direct (float)  %.4g s\n", direct_float_seconds);
    std::printf("  fast    %.4g s  (order %d, theta %.3g, leaf %d)  speed-up %.3g\n", fast_seconds,
                stats.order, stats.opening_angle, stats.leaf_size, direct_seconds / fast_seconds);
    std::printf("  relative L2 error: gradient %.3g, energy %.3g (over %ld targets)\n", gradient_error,
                energy_error, static_cast<long>(error_targets));
  }
  return 0;
}

const bool registered = register_command(
    {{"bench", "coulomb"},
     "Coulomb gradient: seconds per evaluation, fast multipole vs direct summation, and the fast error",
     [](CLI::App& app) {
       app.add_option("--n", args.n, "number of points (with --mesh: points sampled on its surface)");
       app.add_option("--distribution", args.distribution, "uniform (cube), sphere (surface) or clustered")
           ->check(one_of({"uniform", "sphere", "clustered"}));
       app.add_option("--mesh", args.mesh, "use a mesh's vertices (or points on its surface with --n)");
       app.add_option("--repeats", args.repeats, "timed runs per method; the median is reported")
           ->check(integer_at_least(1));
       app.add_option("--accuracy", args.accuracy, "fast summation's target relative L2 gradient error");
       app.add_option("--order", args.order, "override the expansion order (0: from --accuracy)");
       app.add_option("--theta", args.opening_angle, "override the opening angle (0: from --accuracy)");
       app.add_option("--leaf-size", args.leaf_size, "override the leaf size (0: from --accuracy)");
       app.add_option("--sample", args.sample, "error targets when the full direct sum is skipped");
       app.add_option("--full-direct-max", args.full_direct_max,
                      "largest n summed completely by direct summation");
       app.add_option("--seed", args.seed, "random seed for points and the error sample");
       app.add_flag("--json", args.json, "print JSON on stdout");
     },
     run});

}  // namespace
}  // namespace cshapes::cli
