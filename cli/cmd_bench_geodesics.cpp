// cshapes bench geodesics (--vertices N | --mesh FILE [--vertices N]) --json: all-pairs geodesic distances by
// our block heat method against CGAL's Heat_method_3 one source at a time, with errors against exact
// geodesics (experiments/bench_geodesics.h).
#include <iostream>

#include "cli/command.h"
#include "cshapes/support/format.h"
#include "cshapes/experiments/bench_geodesics.h"

namespace cshapes::cli {
namespace cmd_bench_geodesics {
namespace {

GeodesicsBenchOptions options;
std::string heat_mode = "idt";
int vertices =
    0;  // --vertices: a torus of N vertices, or --mesh refined to N (one meaning: the vertex count)
bool json = false;

int run() {
  if (options.mesh.empty() && vertices > 0 && vertices < 16)
    usage_fail("--vertices: a torus of at least 16 vertices, got ", vertices);
  (options.mesh.empty() ? options.n : options.vertices) = vertices;
  options.heat_mode = parse_cgal_heat_mode(heat_mode);
  options.notes = {progress_printer(), note};
  const GeodesicsBenchResult r = bench_geodesics(options);
  if (json)
    std::cout << to_json(r).dump(2) << std::endl;
  else
    // Three significant figures, the errors in % of the exact distances; --json has every digit.
    std::cout << "ours " << seconds_text(r.ours.seconds) << ", anchor " << seconds_text(r.anchor.seconds)
              << (r.anchor_extrapolated ? " (extrapolated)" : "") << ", speedup "
              << significant(r.speedup_vs_anchor()) << "; mean relative error vs exact: ours "
              << significant(100 * r.ours.mean_relative_error) << "%, anchor "
              << significant(100 * r.anchor.mean_relative_error) << "%, fmm "
              << significant(100 * r.fmm.mean_relative_error) << "%" << std::endl;
  return 0;
}

const bool registered = register_command(
    {{"bench", "geodesics"},
     "All-pairs geodesics: our block heat method vs CGAL's Heat_method_3 one source at a time, errors vs "
     "exact",
     [](CLI::App& app) {
       app.add_option(
              "--vertices", vertices,
              "without --mesh: a torus of exactly N vertices (at least 16); with --mesh: the mesh refined "
              "to exactly N vertices (1-to-4 subdivision, then longest-edge splits), 0: as it is")
           ->check(integer_in(0, 100000000));
       app.add_option("--mesh", options.mesh, "benchmark this mesh");
       app.add_option("--heat-mode", heat_mode, "idt or direct, for both heat methods")
           ->capture_default_str()
           ->check(one_of({"idt", "direct"}));
       app.add_option("--anchor-samples", options.anchor_samples,
                      "sources timed for CGAL's heat method (n: the full all-pairs run)")
           ->capture_default_str();
       app.add_option("--exact-samples", options.exact_samples, "sources with exact geodesics for the errors")
           ->capture_default_str();
       app.add_option("--fmm-samples", options.fmm_samples, "sources timed for fast marching")
           ->capture_default_str();
       app.add_option("--seed", options.seed, "random seed for the sampled sources")->capture_default_str();
       app.add_flag("--json", json, "print JSON");
     },
     run});

}  // namespace
}  // namespace cmd_bench_geodesics
}  // namespace cshapes::cli
