// cshapes bench icp [--points 5000] [--a A --b B] [--json]: ICP of two ~5,000-point shapes with every
// starting pose (goal: ≤ 20 ms), and the time of one ICP iteration beside Open3D's registration_icp on the
// same points (experiments/bench_icp.h).
#include <cmath>
#include <cstdio>
#include <iostream>

#include "cli/command.h"
#include "cshapes/experiments/bench_icp.h"

namespace cshapes::cli {
namespace cmd_bench_icp {
namespace {

IcpBenchOptions options;
bool json = false, no_open3d = false;

int run() {
  options.open3d = !no_open3d;
  const IcpBenchResult r = bench_icp(options);
  if (options.open3d && !r.open3d_measured) note("Open3D comparison skipped: " + r.open3d_skipped);
  if (json) {
    std::cout << to_json(r).dump(2) << std::endl;
    return 0;
  }
  std::printf("ICP %s: %ld vs %ld points, %zu starts\n", r.shapes.c_str(), static_cast<long>(r.source_points),
              static_cast<long>(r.target_points), r.starts);
  // Three significant figures, distances in B's units with their share of B's bounding-box diagonal (as
  // align prints them); --json has every digit.
  const double diagonal = r.target_bbox_diagonal;
  const auto share = [&](double x) { return diagonal > 0 ? 100 * x / diagonal : std::nan(""); };
  std::printf(
      "  total (build + align, one thread): CPU %.3g ms, wall %.3g ms (goal 20 ms; load average %.1f)\n",
      r.total_cpu_ms, r.total_wall_ms, r.load_average);
  std::printf("  distances in B's units (%% of B's bounding-box diagonal, %.3g)\n", diagonal);
  std::printf("  without refinement on all points: CPU %.3g ms, wall %.3g ms, hausdorff %.3g (%.3g%%)\n",
              r.no_refine_total_cpu_ms, r.no_refine_total_wall_ms, r.no_refine_hausdorff,
              share(r.no_refine_hausdorff));
  std::printf("  rmse %.3g (%.3g%%), hausdorff %.3g (%.3g%%), reflection %d\n", r.rmse, share(r.rmse),
              r.hausdorff, share(r.hausdorff), r.reflection ? 1 : 0);
  std::printf("  per iteration (wall / CPU): ours %.3g / %.3g ms", r.ours_ms_per_iteration,
              r.ours_cpu_ms_per_iteration);
  if (r.open3d_measured)
    std::printf(", Open3D %.3g / %.3g ms, ratio %.3g / %.3g", r.open3d_ms_per_iteration,
                r.open3d_cpu_ms_per_iteration, r.ratio_open3d_over_ours(), r.ratio_open3d_over_ours_cpu());
  std::printf("\n");
  return 0;
}

const bool registered = register_command(
    {{"bench", "icp"},
     "ICP of two 5,000-point shapes with every starting pose (goal <= 20 ms); per-iteration time vs Open3D",
     [](CLI::App& app) {
       app.add_option("--points", options.n, "points per shape (subsampled; 0 keeps all)")
           ->check(integer_at_least(0));
       app.add_option("--a", options.a, "source shape (default: TOSCA cat0 from the shared data)");
       app.add_option("--b", options.b, "target shape (default: TOSCA cat1)");
       app.add_option("--repeats", options.repeats, "timed repetitions (median reported)")
           ->check(integer_at_least(1));
       app.add_flag("--json", json, "print JSON");
       app.add_flag("--no-open3d", no_open3d, "skip the Open3D comparison");
       app.add_option(
           "--python", options.python,
           "interpreter with Open3D (default: $CSHAPES_PYTHON, /usr/bin/python3 or python3, the first "
           "that imports it)");
     },
     run});

}  // namespace
}  // namespace cmd_bench_icp
}  // namespace cshapes::cli
