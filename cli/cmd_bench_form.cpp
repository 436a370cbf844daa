// cshapes bench form (--mesh FILE | --vertices N) --method M [--mds-solver S] [--repeats R] [--reference
// cmds|none]
// --json: seconds and peak memory of one canonical form by any method, against full classical MDS in the same
// run (experiments/bench_form.h).
#include <cstdio>
#include <iostream>

#include "cshapes/canon/landmark_mds.h"
#include "cli/command.h"
#include "cshapes/support/format.h"
#include "cshapes/experiments/bench_form.h"
#include "cshapes/pipeline/canonical_form_methods.h"

namespace cshapes::cli {
namespace cmd_bench_form {
namespace {

FormBenchOptions options;
std::string reference = "cmds";
bool json = false;

int run() {
  options.reference = reference == "cmds";
  const FormBenchResult r = bench_form(options);
  if (json) {
    std::cout << to_json(r).dump(2) << std::endl;
    return 0;
  }
  std::printf("%s: %ld vertices, %s form %s (precompute %s), peak RSS %.0f MB (%.0f before); %s\n",
              r.source.c_str(), static_cast<long>(r.vertices), r.options.method.c_str(),
              seconds_text(r.seconds).c_str(), seconds_text(r.precompute_seconds).c_str(), r.peak_rss_mb,
              r.rss_before_mb, r.quality.c_str());
  if (r.reference_ran)
    std::printf("reference, full classical MDS: %s (%.3gx), peak RSS %.0f MB\n",
                seconds_text(r.reference_seconds).c_str(), r.reference_seconds / r.seconds,
                r.reference_peak_rss_mb);
  else
    std::printf("reference skipped: %s\n", r.reference_skipped.c_str());
  return 0;
}

const bool registered = register_command(
    {{"bench", "form"},
     "Seconds and peak memory of one canonical form by any method, against full classical MDS in the same "
     "run",
     [](CLI::App& app) {
       app.add_option("--mesh", options.mesh, "mesh file (default: a torus of --vertices vertices)");
       app.add_option("--vertices", options.n, "vertices of the generated torus")
           ->capture_default_str()
           ->check(integer_in(16, 100000000));
       std::vector<std::string> known;
       for (const CanonicalFormMethod& m : canonical_form_method_registry()) known.push_back(m.name);
       app.add_option("--method", options.method, "one of " + canonical_form_method_list())
           ->capture_default_str()
           ->check(one_of(known));
       app.add_option("--mds-solver", options.mds_solver,
                      "cmds, smacof: full, landmarks or auto (default: the library's, auto)")
           ->check(one_of(mds_solver_names()));
       app.add_option("--repeats", options.repeats, "forms timed (median reported)")
           ->capture_default_str()
           ->check(integer_at_least(1));
       app.add_option("--reference", reference,
                      "cmds: also time full classical MDS of heat geodesics once, after the forms (skipped, "
                      "with the reason, when its n × n matrix does not fit); none: do not")
           ->capture_default_str()
           ->check(one_of({"cmds", "none"}));
       app.add_flag("--json", json, "print JSON");
     },
     run});

}  // namespace
}  // namespace cmd_bench_form
}  // namespace cshapes::cli
