#include "cshapes/experiments/bench_coulomb.h"

#include <omp.h>

#include <algorithm>
#include <numeric>
#include <random>

#include "cshapes/canon/coulomb_energy.h"
#include "cshapes/support/error.h"
#include "cshapes/mesh/io.h"
#include "cshapes/support/timing.h"
#include "cshapes/experiments/bench_support.h"

namespace cshapes {

namespace {

// The wall-clock and process CPU seconds of the timed runs of one method.
struct Timings {
  std::vector<double> wall, cpu;
  template <class F>
  void run(F&& f) {
    const Stopwatch stopwatch;
    f();
    wall.push_back(stopwatch.wall_seconds());
    cpu.push_back(stopwatch.cpu_seconds());
  }
  // The median wall seconds; cpu_seconds gets the median CPU seconds.
  double median_seconds(double& cpu_seconds) const {
    cpu_seconds = median(cpu);
    return median(wall);
  }
};

// The last run's counts with each phase's median over the runs.
CoulombFmmStats median_phases(const std::vector<CoulombFmmStats>& runs) {
  CoulombFmmStats out = runs.back();
  for (double CoulombFmmStats::*phase :
       {&CoulombFmmStats::seconds_tree, &CoulombFmmStats::seconds_upward, &CoulombFmmStats::seconds_traversal,
        &CoulombFmmStats::seconds_interactions, &CoulombFmmStats::seconds_m2l, &CoulombFmmStats::seconds_p2p}) {
    std::vector<double> values;
    for (const CoulombFmmStats& s : runs) values.push_back(s.*phase);
    out.*phase = median(values);
  }
  return out;
}

}  // namespace

CoulombBenchResult bench_coulomb(const CoulombBenchOptions& options) {
  CSHAPES_REQUIRE(options.repeats >= 1, "bench coulomb: repeats must be >= 1, got ", options.repeats);
  CSHAPES_REQUIRE(options.fast_repeats >= 1, "bench coulomb: fast repeats must be >= 1, got ",
                  options.fast_repeats);
  CoulombBenchResult result;
  result.options = options;
  std::mt19937_64 rng(options.seed);
  Points X;
  if (!options.mesh.empty()) {
    const Mesh mesh = read_mesh(options.mesh);
    if (options.n <= 0 || options.n == mesh.V.rows()) {
      X = mesh.V;
      result.distribution = "mesh-vertices:" + options.mesh;
    } else {
      CSHAPES_REQUIRE(mesh.F.rows() > 0, "bench coulomb: ", options.mesh,
                      " has no faces to sample points on");
      X = sample_surface(mesh, options.n, rng);
      result.distribution = "mesh-surface:" + options.mesh;
    }
  } else {
    CSHAPES_REQUIRE(options.n >= 2, "bench coulomb: --points must be at least 2 (or give --mesh)");
    X = random_points(options.n, options.distribution, rng);
    result.distribution = to_string(options.distribution);
  }
  const Index n = X.rows();
  result.n = n;
  result.threads = omp_get_max_threads();

  CoulombFmmOptions fmm_options;
  fmm_options.accuracy = options.accuracy;
  fmm_options.order = options.order;
  fmm_options.opening_angle = options.opening_angle;
  fmm_options.leaf_size = options.leaf_size;
  fmm_options.want_potentials = true;
  CoulombEvaluation fast;
  Timings fast_runs, direct_runs, float_runs;
  // Each timed run's phases, so that the reported phases are medians like the wall time (one run's phases
  // swing with a shared machine's spells).
  std::vector<CoulombFmmStats> timed_stats;
  auto run_fast = [&] { fast = coulomb_fmm(X, fmm_options, &result.stats); };
  auto time_fast = [&] {
    fast_runs.run(run_fast);
    timed_stats.push_back(result.stats);
  };
  // One untimed run first: the first evaluation of a process pays for the allocator's growth (fresh pages,
  // the heap's thresholds), which the Coulomb iteration's thousands of evaluations do not.
  run_fast();

  CoulombErrors errors;
  if (n <= options.full_direct_max) {
    // The methods take turns (rounds of fast runs, one direct run in double, one in float), so that a slow
    // spell of a shared machine, seconds long, falls on both sides of the ratio. A round's fast runs follow
    // an untimed one: the direct sums leave the fast sum's data out of the caches.
    CoulombEvaluation direct;
    for (int round = 0; round < options.repeats; ++round) {
      if (round > 0) run_fast();
      const int runs = options.fast_repeats * (round + 1) / options.repeats -
                       options.fast_repeats * round / options.repeats;
      for (int r = 0; r < runs; ++r) time_fast();
      direct_runs.run([&] { direct = coulomb_direct(X); });
      float_runs.run([&] { coulomb_direct_float(X); });
    }
    result.fast_seconds = fast_runs.median_seconds(result.fast_cpu_seconds);
    result.direct_seconds = direct_runs.median_seconds(result.direct_cpu_seconds);
    result.direct_float_seconds = float_runs.median_seconds(result.direct_float_cpu_seconds);
    result.direct_float_measured = true;
    result.error_targets = n;
    errors = coulomb_errors(fast, direct);
  } else {
    for (int r = 0; r < options.fast_repeats; ++r) time_fast();
    result.fast_seconds = fast_runs.median_seconds(result.fast_cpu_seconds);
    result.error_targets = std::min(options.sample, n);
    std::vector<Index> all(n);
    std::iota(all.begin(), all.end(), Index(0));
    for (Index t = 0; t < result.error_targets; ++t)  // partial Fisher–Yates: distinct random targets
      std::swap(all[t], all[t + std::uniform_int_distribution<Index>(0, n - 1 - t)(rng)]);
    const std::vector<Index> targets(all.begin(), all.begin() + result.error_targets);
    CoulombTargetSums exact;
    direct_runs.run([&] { exact = coulomb_direct_targets(X, targets); });
    const double sample_seconds = direct_runs.median_seconds(result.direct_cpu_seconds);
    const double scale = double(n) / double(result.error_targets);
    result.direct_seconds = sample_seconds * scale;
    result.direct_cpu_seconds *= scale;
    result.direct_extrapolated = true;
    errors = coulomb_errors(fast, targets, exact);
  }
  result.stats = median_phases(timed_stats);
  result.gradient_rel_error = errors.gradient;
  result.energy_rel_error = errors.energy;
  return result;
}

nlohmann::json to_json(const CoulombBenchResult& r) {
  const CoulombFmmStats& stats = r.stats;
  nlohmann::json j = {{"n", r.n},
                      {"distribution", r.distribution},
                      {"direct_seconds", r.direct_seconds},
                      {"direct_extrapolated", r.direct_extrapolated},
                      {"fast_seconds", r.fast_seconds},
                      {"direct_cpu_seconds", r.direct_cpu_seconds},
                      {"fast_cpu_seconds", r.fast_cpu_seconds},
                      {"speedup", r.speedup()},
                      {"gradient_rel_error", r.gradient_rel_error},
                      {"energy_rel_error", r.energy_rel_error},
                      {"error_targets", r.error_targets},
                      {"threads", r.threads},
                      {"accuracy", r.options.accuracy},
                      {"order", stats.order},
                      {"opening_angle", stats.opening_angle},
                      {"leaf_size", stats.leaf_size},
                      {"repeats", r.options.repeats},
                      {"fast_repeats", r.options.fast_repeats},
                      {"cells", stats.cells},
                      {"m2l_interactions", stats.m2l_interactions},
                      {"p2p_interactions", stats.p2p_interactions},
                      {"fast_phase_seconds",
                       {{"tree", stats.seconds_tree},
                        {"upward", stats.seconds_upward},
                        {"traversal", stats.seconds_traversal},
                        {"interactions", stats.seconds_interactions},
                        {"m2l_thread_seconds", stats.seconds_m2l},
                        {"p2p_thread_seconds", stats.seconds_p2p}}}};
  if (r.direct_float_measured) {
    j["direct_float_seconds"] = r.direct_float_seconds;
    j["direct_float_cpu_seconds"] = r.direct_float_cpu_seconds;
    j["speedup_vs_direct_float"] = r.speedup_vs_direct_float();
  }
  j["build"] = build_json();
  return j;
}

}  // namespace cshapes
