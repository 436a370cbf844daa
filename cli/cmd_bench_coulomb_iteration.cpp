// cshapes bench coulomb-iteration (--mesh FILE | --vertices N) [--repeats R] [--windows W] --json
// Seconds of one outer iteration of the Coulomb canonization (1 Coulomb step + 1 projection sweep) against
// the paper's Table 1 (experiments/bench_coulomb_iteration.h).
#include <algorithm>
#include <cstdio>
#include <iostream>

#include "cli/command.h"
#include "cshapes/support/format.h"
#include "cshapes/experiments/bench_coulomb_iteration.h"

namespace cshapes::cli {
namespace cmd_bench_coulomb_iteration {
namespace {

CoulombIterationBenchOptions options;
bool json = false;

int run() {
  const CoulombIterationBenchResult r = bench_coulomb_iteration(options);
  if (json)
    std::cout << to_json(r).dump(2) << std::endl;
  else
    std::printf(
        "%s: %ld vertices, %s per iteration (paper %s): %.3gx; fast sum at 1e-3: %s, %.3gx (medians of %d "
        "windows; windows %s to %s)\n",
        r.source.c_str(), static_cast<long>(r.vertices), seconds_text(r.seconds).c_str(),
        seconds_text(r.paper_seconds).c_str(), r.speedup_vs_paper(), seconds_text(r.seconds_accuracy_1e3).c_str(),
        r.speedup_vs_paper_accuracy_1e3(), r.options.windows,
        seconds_text(*std::min_element(r.window_seconds.begin(), r.window_seconds.end())).c_str(),
        seconds_text(*std::max_element(r.window_seconds.begin(), r.window_seconds.end())).c_str());
  return 0;
}

const bool registered = register_command(
    {{"bench", "coulomb-iteration"},
     "Seconds of one Coulomb outer iteration (1 gradient step + 1 projection sweep) vs the paper's Table 1",
     [](CLI::App& app) {
       app.add_option("--mesh", options.mesh, "mesh file (default: a torus of --vertices vertices)");
       app.add_option("--vertices", options.n, "vertices of the generated torus")
           ->capture_default_str()
           ->check(integer_in(16, 100000000));
       app.add_option("--repeats", options.repeats, "iterations timed per window (their median)")
           ->capture_default_str()
           ->check(integer_in(1, 1000000));
       app.add_option("--windows", options.windows,
                      "windows per setting, the settings taking turns (the median of the windows' medians "
                      "is reported, and each window's)")
           ->capture_default_str()
           ->check(integer_in(1, 1000));
       app.add_option("--fmm-rebuild-every", options.fmm_rebuild_every,
                      "keep the fast sum's tree for this many iterations (see canon --coulomb-fmm-rebuild-every; "
                      "0: the canonization's default); above 1 a window's figure is the median of its cycles' "
                      "means, each cycle holding one rebuild")
           ->capture_default_str()
           ->check(integer_in(0, 1000000));
       app.add_flag("--json", json, "print JSON");
     },
     run});

}  // namespace
}  // namespace cmd_bench_coulomb_iteration
}  // namespace cshapes::cli
