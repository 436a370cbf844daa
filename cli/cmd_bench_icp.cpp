// cshapes bench icp [--n 5000] [--a A --b B] [--json]: ICP of two ~5,000-point shapes with every starting
// pose (goal: ≤ 20 ms), and the time of one ICP iteration beside Open3D's registration_icp on the same
// points. Everything runs on one thread; times are medians (core/timing.h: the upper median), reported as
// wall time and as the thread's CPU time (on a shared machine the wall time includes other processes' time
// slices; see load_average).
//
// Shapes: A and B when given, else TOSCA cat0 and cat1 (two poses: different vertex counts' orders, a real
// non-rigid difference) from the shared data, else two generated non-symmetric blobs. B is moved by a random
// rigid motion (a reflection included) so the alignment has something to undo. With --n, each set is
// subsampled (or, for generated shapes, made) to n points.
//
// Per-iteration comparison (both single-threaded, point-to-point, one direction, all points, no early stop):
//   ours    = (t(K2 steps) − t(K1 steps)) / (K2 − K1) with the trees built beforehand
//   Open3D  = the same difference for registration_icp(max_iteration = K1, K2), run by /usr/bin/python3 with
//             OMP_NUM_THREADS=1 on the very points we used (written to a temporary file).
// ratio = Open3D / ours (above 1: ours is faster).
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <random>
#include <sstream>

#include "core/atomic_file.h"
#include "core/error.h"
#include "core/io.h"
#include "core/synthetic.h"
#include "core/timing.h"
#include "cli/command.h"
#include "matching/icp.h"
#include "matching/shape_distance.h"

namespace cshapes::cli {
namespace {

namespace fs = std::filesystem;

struct BenchIcpArgs {
  Index n = 5000;
  std::string a, b;
  int repeats = 15;
  bool json = false;
  bool no_open3d = false;
} args;

double load_average() {
  std::ifstream in("/proc/loadavg");
  double one_minute = 0;
  in >> one_minute;
  return one_minute;
}

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

std::string default_shape(const std::string& name) {
  std::string dir;
  if (const char* env = std::getenv("CSHAPES_DATA"); env && *env)
    dir = env;
  else
    dir = "../shared/data";  // the data beside a checkout, run from its root (docs/data.md)
  std::string path = dir + "/tosca5k/" + name + ".off";
  return fs::exists(path) ? path : "";
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

int run() {
  std::string path_a = args.a.empty() ? default_shape("cat0") : args.a;
  std::string path_b = args.b.empty() ? default_shape("cat1") : args.b;
  Points A, B;
  std::string source;
  if (!path_a.empty() && !path_b.empty()) {
    A = subsample(read_mesh(path_a).V, args.n, 11);
    B = subsample(read_mesh(path_b).V, args.n, 12);
    source = path_a + " vs " + path_b;
  } else {
    A = lumpy_blob(args.n, 11);
    B = lumpy_blob(args.n, 12);
    source = "generated blobs";
  }
  // Move B far from A, reflected: the starts have to find the pose.
  double scale = std::sqrt((B.rowwise() - B.colwise().mean()).rowwise().squaredNorm().mean());
  B = random_rigid_transform(2024, scale, true).apply(B);

  // Whole pipeline, one thread: build both shapes (trees, subsamples) and align with every start.
  // Wall time on a shared machine counts other processes' time slices; CPU time of this thread does not.
  struct Timing {
    std::vector<double> build_wall, align_wall, total_wall, total_cpu;
    IcpResult result;
  };
  auto measure = [&](const IcpOptions& options) {
    Timing t;
    for (int r = 0; r < args.repeats; ++r) {
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
  };
  IcpOptions options;
  Timing full = measure(options);
  IcpOptions fast = options;
  fast.refine_on_all_points = false;
  Timing quick = measure(fast);
  const IcpResult& result = full.result;
  ShapeDistance distance = shape_distance(result), quick_distance = shape_distance(quick.result);

  // Per-iteration time, ours.
  const int k1 = 5, k2 = 35;
  IcpOptions plain;
  plain.pyramid = {};
  IcpShape pa(A, plain), pb(B, plain);
  std::vector<double> ours, ours_cpu;
  for (int r = 0; r < std::max(3, args.repeats / 3); ++r) {
    double c0 = thread_cpu_seconds();
    double wall = our_iterations_seconds(pa, pb, k2);
    double c1 = thread_cpu_seconds();
    wall -= our_iterations_seconds(pa, pb, k1);
    double c2 = thread_cpu_seconds();
    ours.push_back(wall / (k2 - k1));
    ours_cpu.push_back(((c1 - c0) - (c2 - c1)) / (k2 - k1));
  }
  double ours_per_iteration = median(ours), ours_cpu_per_iteration = median(ours_cpu);

  nlohmann::json j;
  j["benchmark"] = "icp";
  j["shapes"] = source;
  j["source_points"] = A.rows();
  j["target_points"] = B.rows();
  j["starts"] = result.start_transforms.size();
  j["repeats"] = args.repeats;
  j["load_average"] = load_average();
  j["threads"] = 1;
  j["goal_total_ms"] = 20;
  j["total_cpu_ms_median"] = 1e3 * median(full.total_cpu);
  j["total_wall_ms_median"] = 1e3 * median(full.total_wall);
  j["build_wall_ms_median"] = 1e3 * median(full.build_wall);
  j["align_wall_ms_median"] = 1e3 * median(full.align_wall);
  j["no_refine_total_cpu_ms_median"] = 1e3 * median(quick.total_cpu);
  j["no_refine_total_wall_ms_median"] = 1e3 * median(quick.total_wall);
  j["no_refine_hausdorff"] = quick_distance.hausdorff;
  j["no_refine_chamfer"] = quick_distance.chamfer;
  j["rmse"] = result.rmse;
  j["hausdorff"] = distance.hausdorff;
  j["chamfer"] = distance.chamfer;
  j["reflection"] = result.transform.is_reflection();
  j["iterations_all_points"] = result.iterations;
  j["iterations_total"] = result.total_iterations;
  j["ours_ms_per_iteration"] = 1e3 * ours_per_iteration;
  j["ours_cpu_ms_per_iteration"] = 1e3 * ours_cpu_per_iteration;

  if (!args.no_open3d) {
    // Same points, same single-direction point-to-point iterations, one thread.
    fs::path dir = fs::temp_directory_path() / ("cshapes-bench-icp-" + std::to_string(::getpid()));
    fs::create_directories(dir);
    auto save = [&](const Points& X, const std::string& name) {
      std::string path = (dir / name).string();
      write_file_atomically(path, [&](std::ostream& out) {
        out.precision(17);
        for (Index i = 0; i < X.rows(); ++i) out << X(i, 0) << ' ' << X(i, 1) << ' ' << X(i, 2) << '\n';
      });
      return path;
    };
    std::string fa = save(A, "a.xyz"), fb = save(B, "b.xyz"), out = (dir / "open3d.txt").string();
    std::ostringstream py;
    py << "import time, numpy as np, open3d as o3d\n"
       << "a = o3d.geometry.PointCloud(o3d.utility.Vector3dVector(np.loadtxt('" << fa << "')))\n"
       << "b = o3d.geometry.PointCloud(o3d.utility.Vector3dVector(np.loadtxt('" << fb << "')))\n"
       << "est = o3d.pipelines.registration.TransformationEstimationPointToPoint()\n"
       << "def run(k):\n"
       << "    c = o3d.pipelines.registration.ICPConvergenceCriteria(relative_fitness=0, relative_rmse=0, "
          "max_iteration=k)\n"
       << "    t, p = time.perf_counter(), time.process_time()\n"
       << "    o3d.pipelines.registration.registration_icp(a, b, 1e30, np.eye(4), est, c)\n"
       << "    return time.perf_counter() - t, time.process_time() - p\n"
       << "wall, cpu = [], []\n"
       << "for _ in range(" << std::max(3, args.repeats / 3) << "):\n"
       << "    (w2, c2), (w1, c1) = run(" << k2 << "), run(" << k1 << ")\n"
       << "    wall.append((w2 - w1) / " << (k2 - k1) << "); cpu.append((c2 - c1) / " << (k2 - k1) << ")\n"
       << "wall.sort(); cpu.sort()\n"
       << "open('" << out
       << "', 'w').write('%r %r %s' % (wall[len(wall) // 2], cpu[len(cpu) // 2], o3d.__version__))\n";
    std::string script = (dir / "bench.py").string();
    write_file_atomically(script, [&](std::ostream& s) { s << py.str(); });
    std::string command = "OMP_NUM_THREADS=1 /usr/bin/python3 '" + script + "' >/dev/null 2>&1";
    int status = std::system(command.c_str());
    double open3d_per_iteration = 0, open3d_cpu_per_iteration = 0;
    std::string version;
    std::ifstream in(out);
    if (status == 0 && (in >> open3d_per_iteration >> open3d_cpu_per_iteration >> version) &&
        open3d_per_iteration > 0) {
      j["open3d_version"] = version;
      j["open3d_ms_per_iteration"] = 1e3 * open3d_per_iteration;
      j["open3d_cpu_ms_per_iteration"] = 1e3 * open3d_cpu_per_iteration;
      j["ratio_open3d_over_ours"] = open3d_per_iteration / ours_per_iteration;
      j["ratio_open3d_over_ours_cpu"] = open3d_cpu_per_iteration / ours_cpu_per_iteration;
    } else {
      note("Open3D comparison skipped: /usr/bin/python3 with open3d failed (exit status " +
           std::to_string(status) + ")");
      j["open3d_ms_per_iteration"] = nullptr;
    }
    fs::remove_all(dir);
  }

  if (args.json) {
    std::cout << j.dump(2) << std::endl;
  } else {
    std::printf("ICP %s: %ld vs %ld points, %zu starts\n", source.c_str(), static_cast<long>(A.rows()),
                static_cast<long>(B.rows()), result.start_transforms.size());
    std::printf(
        "  total (build + align, one thread): CPU %.2f ms, wall %.2f ms (goal 20; load average %.1f)\n",
        j["total_cpu_ms_median"].get<double>(), j["total_wall_ms_median"].get<double>(), load_average());
    std::printf("  without refinement on all points: CPU %.2f ms, wall %.2f ms, hausdorff %.4g\n",
                j["no_refine_total_cpu_ms_median"].get<double>(),
                j["no_refine_total_wall_ms_median"].get<double>(), quick_distance.hausdorff);
    std::printf("  rmse %.4g, hausdorff %.4g, reflection %d\n", result.rmse, distance.hausdorff,
                result.transform.is_reflection() ? 1 : 0);
    std::printf("  per iteration (wall / CPU): ours %.3f / %.3f ms", 1e3 * ours_per_iteration,
                1e3 * ours_cpu_per_iteration);
    if (j.contains("ratio_open3d_over_ours"))
      std::printf(", Open3D %.3f / %.3f ms, ratio %.2f / %.2f", j["open3d_ms_per_iteration"].get<double>(),
                  j["open3d_cpu_ms_per_iteration"].get<double>(), j["ratio_open3d_over_ours"].get<double>(),
                  j["ratio_open3d_over_ours_cpu"].get<double>());
    std::printf("\n");
  }
  return 0;
}

const bool registered = register_command(
    {{"bench", "icp"},
     "ICP of two 5,000-point shapes with every starting pose (goal <= 20 ms); per-iteration time vs Open3D",
     [](CLI::App& app) {
       app.add_option("--n", args.n, "points per shape (subsampled; 0 keeps all)")
           ->check(integer_at_least(0));
       app.add_option("--a", args.a, "source shape (default: TOSCA cat0 from the shared data)");
       app.add_option("--b", args.b, "target shape (default: TOSCA cat1)");
       app.add_option("--repeats", args.repeats, "timed repetitions (median reported)")
           ->check(integer_at_least(1));
       app.add_flag("--json", args.json, "print JSON");
       app.add_flag("--no-open3d", args.no_open3d, "skip the Open3D comparison");
     },
     run});

}  // namespace
}  // namespace cshapes::cli
