// cshapes bench smacof: seconds per SMACOF iteration on an n×n geodesic distance matrix, beside
// scikit-learn's sklearn.manifold.smacof on the same matrix and start; also classical MDS time, peak memory
// and, with --acceleration, the passes RRE and MPE need to reach the plain iteration's stress
// (experiments/bench_smacof.h). Prints JSON with --json; the stages' figures go to stderr as they are
// measured.
#include <iostream>

#include "cli/command.h"
#include "cshapes/canon/smacof.h"
#include "cshapes/experiments/bench_smacof.h"

namespace cshapes::cli {
namespace cmd_bench_smacof {
namespace {

SmacofBenchOptions options;
std::string geodesics = "fmm", reference = "auto";
bool json = false;

int run() {
  options.geodesics = parse_geodesic_method(geodesics);
  options.reference = reference == "none"      ? SmacofBenchReference::None
                      : reference == "sklearn" ? SmacofBenchReference::Sklearn
                                               : SmacofBenchReference::Auto;
  options.notes = {progress_printer(), note};
  const SmacofBenchResult r = bench_smacof(options);
  if (json) std::cout << to_json(r).dump(2) << std::endl;
  return 0;
}

const bool registered = register_command(
    {{"bench", "smacof"},
     "SMACOF seconds per iteration vs scikit-learn on the same geodesic distance matrix",
     [](CLI::App& app) {
       app.add_option("--points", options.n, "points of the generated Swiss-roll geodesic matrix")
           ->capture_default_str()
           ->check(integer_in(4, 100000000));
       app.add_option("--mesh", options.mesh,
                      "use the all-pairs geodesics of this mesh instead (start: the mesh)");
       app.add_option("--geodesics", geodesics, "geodesic method for --mesh")->capture_default_str();
       app.add_option("--distances", options.distances,
                      "use this distance matrix (.bin) instead (start: cmds)");
       app.add_option("--iterations", options.iterations, "timed iterations")
           ->capture_default_str()
           ->check(integer_at_least(1));
       app.add_option("--rounds", options.rounds,
                      "ours and scikit-learn take turns this many times; each side's median is reported")
           ->check(integer_at_least(1));
       app.add_option("--reference", reference, "auto (sklearn when it fits), sklearn or none")
           ->capture_default_str()
           ->check(one_of({"auto", "sklearn", "none"}));
       app.add_option(
           "--python", options.python,
           "interpreter with scikit-learn (default: $CSHAPES_PYTHON, /usr/bin/python3 or python3, the "
           "first that imports it)");
       app.add_flag("--acceleration", options.acceleration,
                    "also count iterations of plain, RRE and MPE SMACOF to the same stress (from cmds)");
       // SMACOF's settings, named and limited as the method option names them (canon --method smacof).
       app.add_option("--smacof-tolerance", options.tolerance,
                      "--acceleration: plain SMACOF's stopping tolerance")
           ->capture_default_str()
           ->check(within(smacof_limits::kTolerance));
       app.add_option("--smacof-max-iterations", options.max_iterations,
                      "--acceleration: maximum iterations of each run")
           ->capture_default_str()
           ->check(within(smacof_limits::kIterations));
       app.add_option("--smacof-window", options.window, "--acceleration: Guttman steps per extrapolation")
           ->capture_default_str()
           ->check(within(smacof_limits::kWindow));
       app.add_option("--seed", options.seed, "random seed of the generated samples")->capture_default_str();
       app.add_flag("--json", json, "print the results as JSON on stdout");
     },
     run});

}  // namespace
}  // namespace cmd_bench_smacof
}  // namespace cshapes::cli
