// The ICP benchmark (`cshapes bench icp`): ICP (matching/icp.h) of two ~5,000-point shapes with every
// starting pose (goal: ≤ 20 ms), and the time of one ICP iteration beside Open3D's registration_icp on the
// same points. Everything runs on one thread; times are medians (support/timing.h: the upper median) of
// `repeats` runs, as wall time and as the thread's CPU time (on a shared machine the wall time includes other
// processes' time slices; see load_average).
//
// Shapes: a and b when given, else TOSCA cat0 and cat1 (two poses: different vertex orders, a real non-rigid
// difference) from the shared data (experiments/bench_support.h), else two generated non-symmetric blobs
// (data/synthetic.h lumpy_blob). B is moved by a random rigid motion (a reflection included) so the alignment
// has something to undo. With n > 0, each set is subsampled (or, for generated shapes, made) to n points.
//
// Per-iteration comparison (both single-threaded, point-to-point, one direction, all points, no early stop):
//   ours    = (t(K2 steps) − t(K1 steps)) / (K2 − K1) with the trees built beforehand, K1 = 5, K2 = 35
//   Open3D  = the same difference for registration_icp(max_iteration = K1, K2), run by the interpreter that
//             imports numpy and open3d (experiments/figures.h find_python) with OMP_NUM_THREADS=1, on the
//             very points we used; medians of max(3, repeats / 3) pairs on both sides.
// ratio = Open3D / ours (above 1: ours is faster). Without Open3D the comparison is skipped, with the reason.
#pragma once

#include <nlohmann/json.hpp>
#include <string>

#include "cshapes/support/types.h"

namespace cshapes {

struct IcpBenchOptions {
  Index n = 5000;      // points per shape (subsampled; 0 keeps all)
  std::string a, b;    // source and target mesh files; "": TOSCA cat0 and cat1, else generated blobs
  int repeats = 15;    // timed repetitions (median reported), >= 1
  bool open3d = true;  // measure Open3D's iteration beside ours
  std::string python;  // interpreter for Open3D; "": the first that imports numpy and open3d
};

struct IcpBenchResult {
  IcpBenchOptions options;  // as run
  std::string shapes;       // "A vs B" or "generated blobs"
  Index source_points = 0, target_points = 0;
  size_t starts = 0;        // starting poses tried
  double load_average = 0;  // one-minute load average after the timings
  // The whole alignment, one thread: build both shapes (trees, subsamples) and align with every start.
  double total_cpu_ms = 0, total_wall_ms = 0, build_wall_ms = 0, align_wall_ms = 0;  // medians
  // The same without the final refinement on all points.
  double no_refine_total_cpu_ms = 0, no_refine_total_wall_ms = 0, no_refine_hausdorff = 0,
         no_refine_chamfer = 0;
  double rmse = 0, hausdorff = 0,
         chamfer = 0;       // of the full alignment (matching/shape_distance.h), B's units
  double target_bbox_diagonal = 0;  // B's, as aligned onto: the reference the console gives the distances
  bool reflection = false;  // the alignment found includes a reflection
  int iterations_all_points = 0, iterations_total = 0;
  double ours_ms_per_iteration = 0, ours_cpu_ms_per_iteration = 0;  // medians
  // Open3D's iteration, when measured; otherwise open3d_skipped says why.
  bool open3d_measured = false;
  std::string open3d_skipped;  // why not measured: "--no-open3d", no interpreter, or the script's failure
  std::string open3d_version;
  double open3d_ms_per_iteration = 0, open3d_cpu_ms_per_iteration = 0;
  double ratio_open3d_over_ours() const { return open3d_ms_per_iteration / ours_ms_per_iteration; }
  double ratio_open3d_over_ours_cpu() const {
    return open3d_cpu_ms_per_iteration / ours_cpu_ms_per_iteration;
  }
};

IcpBenchResult bench_icp(const IcpBenchOptions& options);

// {benchmark: "icp", shapes, source_points, target_points, starts, repeats, load_average, threads: 1,
//  goal_total_ms: 20, total_cpu_ms_median, total_wall_ms_median, build_wall_ms_median, align_wall_ms_median,
//  no_refine_total_cpu_ms_median, no_refine_total_wall_ms_median, no_refine_hausdorff, no_refine_chamfer,
//  rmse, hausdorff, chamfer, reflection, iterations_all_points, iterations_total, ours_ms_per_iteration,
//  ours_cpu_ms_per_iteration}; with Open3D measured also open3d_version, open3d_ms_per_iteration,
//  open3d_cpu_ms_per_iteration, ratio_open3d_over_ours, ratio_open3d_over_ours_cpu; when it was tried and
//  could not run, open3d_ms_per_iteration null and open3d_skipped (the reason).
nlohmann::json to_json(const IcpBenchResult& result);

}  // namespace cshapes
