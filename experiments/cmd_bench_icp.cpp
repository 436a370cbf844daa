// cshapes bench icp [--n 5000] [--a A --b B] [--json]: ICP of two ~5,000-point shapes with every starting
// pose (goal: ≤ 20 ms), and the time of one ICP iteration beside Open3D's registration_icp on the same points.
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
#include <omp.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
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
#include "experiments/command.h"
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

double seconds_since(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  return v.empty() ? 0.0 : (v.size() % 2 ? v[v.size() / 2] : 0.5 * (v[v.size() / 2 - 1] + v[v.size() / 2]));
}

// A lumpy, non-symmetric closed blob of n points (no reflection or rotation maps it onto itself).
Points generated_blob(Index n, uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::normal_distribution<double> normal(0.0, 1.0);
  Points X(n, 3);
  for (Index i = 0; i < n; ++i) {
    Eigen::Vector3d u(normal(rng), normal(rng), normal(rng));
    u.normalize();
    double r = 1.0 + 0.3 * std::sin(3 * u.x() + 1) * std::cos(2 * u.y()) + 0.2 * u.z() * u.z() * u.x();
    X.row(i) = (Eigen::Vector3d(3.0, 1.5, 1.0).asDiagonal() * (r * u)).transpose();
  }
  return X;
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
  if (const char* env = std::getenv("CSHAPES_DATA"); env && *env) dir = env;
  else dir = std::string(CSHAPES_SOURCE_DIR) + "/../shared/data";
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
  auto t0 = std::chrono::steady_clock::now();
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
    A = generated_blob(args.n, 11);
    B = generated_blob(args.n, 12);
    source = "generated blobs";
  }
  // Move B far from A, reflected: the starts have to find the pose.
  double scale = std::sqrt((B.rowwise() - B.colwise().mean()).rowwise().squaredNorm().mean());
  B = random_rigid_transform(2024, scale, true).apply(B);

  IcpOptions options;
  // Whole pipeline: build both shapes (trees, subsamples) and align with every start.
  std::vector<double> build_s, align_s, total_s;
  IcpResult result;
  for (int r = 0; r < args.repeats; ++r) {
    auto t0 = std::chrono::steady_clock::now();
    IcpShape sa(A, options), sb(B, options);
    double built = seconds_since(t0);
    auto t1 = std::chrono::steady_clock::now();
    result = icp(sa, sb, options);
    double aligned = seconds_since(t1);
    build_s.push_back(built);
    align_s.push_back(aligned);
    total_s.push_back(built + aligned);
  }
  // The same, single-threaded.
  IcpOptions serial = options;
  serial.parallel = false;
  std::vector<double> serial_s;
  for (int r = 0; r < args.repeats; ++r) {
    auto t0 = std::chrono::steady_clock::now();
    IcpShape sa(A, serial), sb(B, serial);
    IcpResult rs = icp(sa, sb, serial);
    serial_s.push_back(seconds_since(t0));
  }
  ShapeDistance distance = shape_distance(result);

  // Per-iteration time, ours.
  const int k1 = 5, k2 = 35;
  IcpOptions plain;
  plain.pyramid = {};
  IcpShape pa(A, plain), pb(B, plain);
  std::vector<double> ours;
  for (int r = 0; r < std::max(3, args.repeats / 3); ++r)
    ours.push_back((our_iterations_seconds(pa, pb, k2) - our_iterations_seconds(pa, pb, k1)) / (k2 - k1));
  double ours_per_iteration = median(ours);

  nlohmann::json j;
  j["benchmark"] = "icp";
  j["shapes"] = source;
  j["source_points"] = A.rows();
  j["target_points"] = B.rows();
  j["starts"] = result.start_transforms.size();
  j["repeats"] = args.repeats;
  j["build_ms_median"] = 1e3 * median(build_s);
  j["align_ms_median"] = 1e3 * median(align_s);
  j["total_ms_median"] = 1e3 * median(total_s);
  j["total_ms_single_thread_median"] = 1e3 * median(serial_s);
  j["goal_total_ms"] = 20;
  j["threads"] = omp_get_max_threads();
  j["rmse"] = result.rmse;
  j["hausdorff"] = distance.hausdorff;
  j["chamfer"] = distance.chamfer;
  j["reflection"] = result.transform.is_reflection();
  j["iterations_all_points"] = result.iterations;
  j["iterations_total"] = result.total_iterations;
  j["ours_ms_per_iteration"] = 1e3 * ours_per_iteration;

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
       << "    c = o3d.pipelines.registration.ICPConvergenceCriteria(relative_fitness=0, relative_rmse=0, max_iteration=k)\n"
       << "    t = time.perf_counter()\n"
       << "    o3d.pipelines.registration.registration_icp(a, b, 1e30, np.eye(4), est, c)\n"
       << "    return time.perf_counter() - t\n"
       << "per = sorted((run(" << k2 << ") - run(" << k1 << ")) / " << (k2 - k1) << " for _ in range("
       << std::max(3, args.repeats / 3) << "))\n"
       << "open('" << out << "', 'w').write('%r %s' % (per[len(per) // 2], o3d.__version__))\n";
    std::string script = (dir / "bench.py").string();
    write_file_atomically(script, [&](std::ostream& s) { s << py.str(); });
    std::string command = "OMP_NUM_THREADS=1 /usr/bin/python3 '" + script + "' >/dev/null 2>&1";
    int status = std::system(command.c_str());
    double open3d_per_iteration = 0;
    std::string version;
    std::ifstream in(out);
    if (status == 0 && (in >> open3d_per_iteration >> version) && open3d_per_iteration > 0) {
      j["open3d_version"] = version;
      j["open3d_ms_per_iteration"] = 1e3 * open3d_per_iteration;
      j["ratio_open3d_over_ours"] = open3d_per_iteration / ours_per_iteration;
    } else {
      note("Open3D comparison skipped: /usr/bin/python3 with open3d failed (exit status " + std::to_string(status) + ")");
      j["open3d_ms_per_iteration"] = nullptr;
    }
    fs::remove_all(dir);
  }

  if (args.json) {
    std::cout << j.dump(2) << std::endl;
  } else {
    std::printf("ICP %s: %ld vs %ld points, %zu starts\n", source.c_str(), static_cast<long>(A.rows()),
                static_cast<long>(B.rows()), result.start_transforms.size());
    std::printf("  total %.2f ms (build %.2f + align %.2f; goal 20), single thread %.2f ms\n",
                j["total_ms_median"].get<double>(), j["build_ms_median"].get<double>(),
                j["align_ms_median"].get<double>(), j["total_ms_single_thread_median"].get<double>());
    std::printf("  rmse %.4g, hausdorff %.4g, reflection %d\n", result.rmse, distance.hausdorff,
                result.transform.is_reflection() ? 1 : 0);
    std::printf("  per iteration: ours %.3f ms", 1e3 * ours_per_iteration);
    if (j.contains("ratio_open3d_over_ours"))
      std::printf(", Open3D %.3f ms, ratio %.2f", j["open3d_ms_per_iteration"].get<double>(),
                  j["ratio_open3d_over_ours"].get<double>());
    std::printf("\n");
  }
  return 0;
}

const bool registered = register_command(
    {{"bench", "icp"},
     "ICP of two 5,000-point shapes with every starting pose (goal <= 20 ms); per-iteration time vs Open3D",
     [](CLI::App& app) {
       app.add_option("--n", args.n, "points per shape (subsampled; 0 keeps all)")->check(CLI::NonNegativeNumber);
       app.add_option("--a", args.a, "source shape (default: TOSCA cat0 from the shared data)");
       app.add_option("--b", args.b, "target shape (default: TOSCA cat1)");
       app.add_option("--repeats", args.repeats, "timed repetitions (median reported)")->check(CLI::PositiveNumber);
       app.add_flag("--json", args.json, "print JSON");
       app.add_flag("--no-open3d", args.no_open3d, "skip the Open3D comparison");
     },
     run});

}  // namespace
}  // namespace cshapes::cli
