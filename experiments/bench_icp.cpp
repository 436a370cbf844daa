#include "cshapes/experiments/bench_icp.h"

#include <algorithm>
#include <cmath>
#include <random>
#include <sstream>

#include "cshapes/support/atomic_file.h"
#include "cshapes/support/error.h"
#include "cshapes/mesh/io.h"
#include "cshapes/mesh/mesh.h"
#include "cshapes/mesh/rigid_transform.h"
#include "cshapes/data/synthetic.h"
#include "cshapes/support/timing.h"
#include "cshapes/experiments/bench_support.h"
#include "cshapes/matching/icp.h"
#include "cshapes/matching/shape_distance.h"

namespace cshapes {

namespace {

// The per-iteration comparison's step counts: (t(K2) − t(K1)) / (K2 − K1).
constexpr int kSteps1 = 5, kSteps2 = 35;

Points subsample(const Points& X, Index n, uint64_t seed) {
  if (n <= 0 || n >= X.rows()) return X;
  std::vector<int> order(static_cast<size_t>(X.rows()));
  for (size_t i = 0; i < order.size(); ++i) order[i] = static_cast<int>(i);
  std::mt19937_64 rng(seed);
  std::shuffle(order.begin(), order.end(), rng);
  Points Y(n, 3);
  for (Index i = 0; i < n; ++i) Y.row(i) = X.row(order[static_cast<size_t>(i)]);
  return Y;
}

// Time of `steps` single-direction point-to-point ICP steps on all points, trees prebuilt.
double our_iterations_seconds(const IcpShape& a, const IcpShape& b, int steps) {
  IcpOptions o;
  o.pyramid = {};
  o.try_principal_axes = false;
  o.try_identity = true;
  o.symmetric = false;
  o.screening_iterations = steps;
  o.max_iterations = 1;
  o.relative_tolerance = 0;
  o.absolute_tolerance = 0;
  o.parallel = false;
  auto t0 = WallClock::now();
  IcpResult r = icp(a, b, o);
  (void)r;
  return seconds_since(t0);
}

// Whole pipeline, one thread: build both shapes (trees, subsamples) and align with every start, `repeats`
// times. Wall time on a shared machine counts other processes' time slices; CPU time of this thread does not.
struct AlignmentTimings {
  std::vector<double> build_wall, align_wall, total_wall, total_cpu;
  IcpResult result;
};
AlignmentTimings time_alignment(const Points& A, const Points& B, const IcpOptions& options, int repeats) {
  AlignmentTimings t;
  for (int r = 0; r < repeats; ++r) {
    double c0 = thread_cpu_seconds();
    auto t0 = WallClock::now();
    IcpShape sa(A, options), sb(B, options);
    double built = seconds_since(t0);
    auto t1 = WallClock::now();
    t.result = icp(sa, sb, options);
    double aligned = seconds_since(t1);
    t.total_cpu.push_back(thread_cpu_seconds() - c0);
    t.build_wall.push_back(built);
    t.align_wall.push_back(aligned);
    t.total_wall.push_back(built + aligned);
  }
  return t;
}

// Open3D's registration_icp on the same points, the same single-direction point-to-point iterations, one
// thread. Prints "WALL CPU VERSION" (seconds per iteration, medians of `pairs` pairs of runs).
const char* const kOpen3dScript = R"(import sys, time, numpy as np, open3d as o3d
folder, pairs, k1, k2 = sys.argv[1], int(sys.argv[2]), int(sys.argv[3]), int(sys.argv[4])
a = o3d.geometry.PointCloud(o3d.utility.Vector3dVector(np.loadtxt(folder + '/a.xyz')))
b = o3d.geometry.PointCloud(o3d.utility.Vector3dVector(np.loadtxt(folder + '/b.xyz')))
est = o3d.pipelines.registration.TransformationEstimationPointToPoint()
def run(k):
    c = o3d.pipelines.registration.ICPConvergenceCriteria(relative_fitness=0, relative_rmse=0, max_iteration=k)
    t, p = time.perf_counter(), time.process_time()
    o3d.pipelines.registration.registration_icp(a, b, 1e30, np.eye(4), est, c)
    return time.perf_counter() - t, time.process_time() - p
wall, cpu = [], []
for _ in range(pairs):
    (w2, c2), (w1, c1) = run(k2), run(k1)
    wall.append((w2 - w1) / (k2 - k1)); cpu.append((c2 - c1) / (k2 - k1))
wall.sort(); cpu.sort()
print('%r %r %s' % (wall[len(wall) // 2], cpu[len(cpu) // 2], o3d.__version__))
)";

void measure_open3d(const Points& A, const Points& B, int pairs, IcpBenchResult& result) {
  AnchorScript script;
  script.package = "open3d";
  script.imports = "numpy, open3d";
  script.python = result.options.python;
  script.environment = "OMP_NUM_THREADS=1";
  script.source = kOpen3dScript;
  script.arguments = {std::to_string(pairs), std::to_string(kSteps1), std::to_string(kSteps2)};
  script.write_inputs = [&](const std::string& folder) {
    auto save = [](const Points& X, const std::string& path) {
      write_file_atomically(path, [&](std::ostream& out) {
        out.precision(17);
        for (Index i = 0; i < X.rows(); ++i) out << X(i, 0) << ' ' << X(i, 1) << ' ' << X(i, 2) << '\n';
      });
    };
    save(A, folder + "/a.xyz");
    save(B, folder + "/b.xyz");
  };
  const AnchorRun run = run_python_anchor(script);
  double wall = 0, cpu = 0;
  std::string version;
  std::istringstream output(run.output);
  if (run.ran && (output >> wall >> cpu >> version) && wall > 0) {
    result.open3d_measured = true;
    result.open3d_version = version;
    result.open3d_ms_per_iteration = 1e3 * wall;
    result.open3d_cpu_ms_per_iteration = 1e3 * cpu;
  } else {
    result.open3d_skipped = run.ran ? "unexpected output from the Open3D script: " + run.output : run.skipped;
  }
}

}  // namespace

IcpBenchResult bench_icp(const IcpBenchOptions& options) {
  CSHAPES_REQUIRE(options.repeats >= 1, "bench icp: repeats must be >= 1, got ", options.repeats);
  IcpBenchResult result;
  result.options = options;
  const std::string path_a = options.a.empty() ? shared_tosca5k_shape("cat0") : options.a;
  const std::string path_b = options.b.empty() ? shared_tosca5k_shape("cat1") : options.b;
  Points A, B;
  if (!path_a.empty() && !path_b.empty()) {
    A = subsample(read_mesh(path_a).V, options.n, 11);
    B = subsample(read_mesh(path_b).V, options.n, 12);
    result.shapes = path_a + " vs " + path_b;
  } else {
    A = lumpy_blob(options.n, 11);
    B = lumpy_blob(options.n, 12);
    result.shapes = "generated blobs";
  }
  // Move B far from A, reflected: the starts have to find the pose.
  const double scale = std::sqrt((B.rowwise() - B.colwise().mean()).rowwise().squaredNorm().mean());
  B = random_rigid_transform(2024, scale, true).apply(B);
  result.source_points = A.rows();
  result.target_points = B.rows();
  result.target_bbox_diagonal = finite_bbox_diagonal(B);

  IcpOptions with_refinement;
  const AlignmentTimings full = time_alignment(A, B, with_refinement, options.repeats);
  IcpOptions without_refinement = with_refinement;
  without_refinement.refine_on_all_points = false;
  const AlignmentTimings quick = time_alignment(A, B, without_refinement, options.repeats);
  const ShapeDistance distance = shape_distance(full.result), quick_distance = shape_distance(quick.result);
  result.starts = full.result.start_transforms.size();
  result.total_cpu_ms = 1e3 * median(full.total_cpu);
  result.total_wall_ms = 1e3 * median(full.total_wall);
  result.build_wall_ms = 1e3 * median(full.build_wall);
  result.align_wall_ms = 1e3 * median(full.align_wall);
  result.no_refine_total_cpu_ms = 1e3 * median(quick.total_cpu);
  result.no_refine_total_wall_ms = 1e3 * median(quick.total_wall);
  result.no_refine_hausdorff = quick_distance.hausdorff;
  result.no_refine_chamfer = quick_distance.chamfer;
  result.rmse = full.result.rmse;
  result.hausdorff = distance.hausdorff;
  result.chamfer = distance.chamfer;
  result.reflection = full.result.transform.is_reflection();
  result.iterations_all_points = full.result.iterations;
  result.iterations_total = full.result.total_iterations;

  // Per-iteration time, ours.
  IcpOptions plain;
  plain.pyramid = {};
  const IcpShape pa(A, plain), pb(B, plain);
  const int pairs = std::max(3, options.repeats / 3);
  std::vector<double> ours, ours_cpu;
  for (int r = 0; r < pairs; ++r) {
    double c0 = thread_cpu_seconds();
    double wall = our_iterations_seconds(pa, pb, kSteps2);
    double c1 = thread_cpu_seconds();
    wall -= our_iterations_seconds(pa, pb, kSteps1);
    double c2 = thread_cpu_seconds();
    ours.push_back(wall / (kSteps2 - kSteps1));
    ours_cpu.push_back(((c1 - c0) - (c2 - c1)) / (kSteps2 - kSteps1));
  }
  result.ours_ms_per_iteration = 1e3 * median(ours);
  result.ours_cpu_ms_per_iteration = 1e3 * median(ours_cpu);
  result.load_average = load_average();

  if (options.open3d)
    measure_open3d(A, B, pairs, result);
  else
    result.open3d_skipped = "not asked for (--no-open3d)";
  return result;
}

nlohmann::json to_json(const IcpBenchResult& r) {
  nlohmann::json j;
  j["benchmark"] = "icp";
  j["shapes"] = r.shapes;
  j["source_points"] = r.source_points;
  j["target_points"] = r.target_points;
  j["starts"] = r.starts;
  j["repeats"] = r.options.repeats;
  j["load_average"] = r.load_average;
  j["threads"] = 1;
  j["goal_total_ms"] = 20;
  j["total_cpu_ms_median"] = r.total_cpu_ms;
  j["total_wall_ms_median"] = r.total_wall_ms;
  j["build_wall_ms_median"] = r.build_wall_ms;
  j["align_wall_ms_median"] = r.align_wall_ms;
  j["no_refine_total_cpu_ms_median"] = r.no_refine_total_cpu_ms;
  j["no_refine_total_wall_ms_median"] = r.no_refine_total_wall_ms;
  j["no_refine_hausdorff"] = r.no_refine_hausdorff;
  j["no_refine_chamfer"] = r.no_refine_chamfer;
  j["rmse"] = r.rmse;
  j["hausdorff"] = r.hausdorff;
  j["chamfer"] = r.chamfer;
  j["reflection"] = r.reflection;
  j["iterations_all_points"] = r.iterations_all_points;
  j["iterations_total"] = r.iterations_total;
  j["ours_ms_per_iteration"] = r.ours_ms_per_iteration;
  j["ours_cpu_ms_per_iteration"] = r.ours_cpu_ms_per_iteration;
  if (r.open3d_measured) {
    j["open3d_version"] = r.open3d_version;
    j["open3d_ms_per_iteration"] = r.open3d_ms_per_iteration;
    j["open3d_cpu_ms_per_iteration"] = r.open3d_cpu_ms_per_iteration;
    j["ratio_open3d_over_ours"] = r.ratio_open3d_over_ours();
    j["ratio_open3d_over_ours_cpu"] = r.ratio_open3d_over_ours_cpu();
  } else if (r.options.open3d) {
    j["open3d_ms_per_iteration"] = nullptr;
    j["open3d_skipped"] = r.open3d_skipped;
  }
  j["build"] = build_json();
  return j;
}

}  // namespace cshapes
