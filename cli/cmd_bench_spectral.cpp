// cshapes bench spectral (--mesh FILE | --n N) [--method lbo|diffusion] [--repeats R] --json
// Seconds and peak memory of one spectral canonical form (experiments/bench_spectral.h).
#include <cstdio>
#include <iostream>

#include "cli/command.h"
#include "experiments/bench_spectral.h"

namespace cshapes::cli {
namespace {

SpectralBenchOptions options;
bool json = false;

int run() {
  const SpectralBenchResult r = bench_spectral(options);
  if (json)
    std::cout << to_json(r).dump(2) << std::endl;
  else
    std::printf("%s: %ld vertices, %s form %.4g s (eigenpairs %.4g s, %ld products), peak RSS %.0f MB (%.0f "
                "before)\n",
                r.source.c_str(), static_cast<long>(r.vertices), r.options.method.c_str(), r.seconds,
                r.eigen_seconds, static_cast<long>(r.operator_products), r.peak_rss_mb, r.rss_before_mb);
  return 0;
}

const bool registered = register_command(
    {{"bench", "spectral"},
     "Seconds and peak memory of one spectral canonical form (lbo or diffusion)",
     [](CLI::App& app) {
       app.add_option("--mesh", options.mesh, "mesh file (default: a torus of --n vertices)");
       app.add_option("--n", options.n, "vertices of the generated torus")->capture_default_str();
       app.add_option("--method", options.method, "lbo, diffusion or spectral-mds")
           ->capture_default_str()
           ->check(one_of({"lbo", "diffusion", "spectral-mds"}));
       app.add_option("--repeats", options.repeats, "forms timed (median reported)")->capture_default_str();
       app.add_flag("--json", json, "print JSON");
     },
     run});

}  // namespace
}  // namespace cshapes::cli
