// cshapes bench coulomb: seconds per Coulomb gradient, fast (FMM) vs direct summation, and the fast method's
// relative error against direct summation, measured in one run (experiments/bench_coulomb.h).
//
//   cshapes bench coulomb --points 100000 --distribution uniform --json
//   cshapes bench coulomb --mesh ../shared/data/tosca5k/cat0.off --json            (the mesh's vertices)
//   cshapes bench coulomb --mesh ../shared/data/tosca5k/cat0.off --points 100000 --json (points on its
//   surface)
#include <cstdio>
#include <iostream>

#include "cli/command.h"
#include "cshapes/support/format.h"
#include "cshapes/experiments/bench_coulomb.h"

namespace cshapes::cli {
namespace cmd_bench_coulomb {
namespace {

CoulombBenchOptions options;
std::string distribution = "uniform";
bool json = false;

int run() {
  options.distribution = parse_point_distribution(distribution);
  const CoulombBenchResult r = bench_coulomb(options);
  if (json) {
    std::cout << to_json(r).dump(2) << std::endl;
    return 0;
  }
  std::printf("n %ld (%s), %d threads\n", static_cast<long>(r.n), r.distribution.c_str(), r.threads);
  std::printf("  direct  %s%s\n", seconds_text(r.direct_seconds).c_str(),
              r.direct_extrapolated ? " (extrapolated from the sample)" : "");
  if (r.direct_float_measured)
    std::printf("  direct (float)  %s\n", seconds_text(r.direct_float_seconds).c_str());
  std::printf("  fast    %s  (order %d, theta %.3g, leaf %d)  speed-up %.3g\n",
              seconds_text(r.fast_seconds).c_str(), r.stats.order, r.stats.opening_angle, r.stats.leaf_size,
              r.speedup());
  std::printf("  relative L2 error: gradient %.3g, energy %.3g (over %ld targets)\n", r.gradient_rel_error,
              r.energy_rel_error, static_cast<long>(r.error_targets));
  return 0;
}

const bool registered = register_command(
    {{"bench", "coulomb"},
     "Coulomb gradient: seconds per evaluation, fast multipole vs direct summation, and the fast error",
     [](CLI::App& app) {
       app.add_option("--points", options.n, "number of points (with --mesh: points sampled on its surface)")
           ->check(integer_in(0, 100000000));
       app.add_option("--distribution", distribution, "uniform (cube), sphere (surface) or clustered")
           ->check(one_of({"uniform", "sphere", "clustered"}));
       app.add_option("--mesh", options.mesh,
                      "use a mesh's vertices (or points on its surface with --points)");
       app.add_option("--repeats", options.repeats,
                      "timed runs of each direct sum, taking turns with the fast runs; the median is reported")
           ->check(integer_at_least(1));
       app.add_option("--fast-repeats", options.fast_repeats,
                      "timed runs of the fast sum, after one untimed run; the median is reported")
           ->check(integer_at_least(1));
       app.add_option("--accuracy", options.accuracy, "fast summation's target relative L2 gradient error")
           ->check(number_above(0));
       app.add_option("--order", options.order, "override the expansion order (0: from --accuracy)")
           ->check(integer_in(0, 16));
       app.add_option("--theta", options.opening_angle, "override the opening angle (0: from --accuracy)")
           ->check(number_in(0, 0.999));
       app.add_option("--leaf-size", options.leaf_size, "override the leaf size (0: from --accuracy)")
           ->check(integer_in(0, 100000));
       app.add_option("--sample", options.sample, "error targets when the full direct sum is skipped")
           ->check(integer_at_least(1));
       app.add_option("--full-direct-max", options.full_direct_max,
                      "largest n summed completely by direct summation");
       app.add_option("--seed", options.seed, "random seed for points and the error sample");
       app.add_flag("--json", json, "print JSON on stdout");
     },
     run});

}  // namespace
}  // namespace cmd_bench_coulomb
}  // namespace cshapes::cli
