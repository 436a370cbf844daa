// cshapes bench smacof: seconds per SMACOF iteration on an n×n geodesic distance matrix, beside
// scikit-learn's sklearn.manifold.smacof on the same matrix and start (run with /usr/bin/python3 when it has
// scikit-learn); also classical MDS time, peak memory and, with --acceleration, the passes RRE and MPE need
// to reach the plain iteration's stress.
//
// The default matrix needs no mesh: n points drawn uniformly on the unrolled Swiss roll (the paper's
// swissroll, scaled to n), whose geodesic distances are exactly the Euclidean distances in the flat unrolled
// rectangle.
#include <omp.h>
#include <sys/resource.h>
#include <unistd.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <random>

#include "canon/classical_mds.h"
#include "canon/smacof.h"
#include "core/error.h"
#include "core/geodesics.h"
#include "core/synthetic.h"
#include "cli/command.h"

namespace cshapes::cli {
namespace {

struct BenchArgs {
  Index n = 3505;
  std::string mesh, distances;
  std::string geodesics = "fmm";
  int iterations = 10;
  std::string reference = "auto";
  std::string python = "/usr/bin/python3";
  bool acceleration = false;
  double tolerance = 1e-5;
  int max_iterations = 1000;
  int window = 6;
  unsigned seed = 1;
  bool json = false;
} args;

double peak_rss_mb() {
  rusage usage{};
  getrusage(RUSAGE_SELF, &usage);
  return usage.ru_maxrss / 1024.0;  // Linux: kilobytes
}

// scikit-learn's smacof on the same matrix and start, timed inside Python. Null with a reason when
// unavailable.
nlohmann::json sklearn_reference(const DistanceMatrix& D, const Points& X0, int iterations) {
  const Index n = D.rows();
  // sklearn holds D and several n×n float64 work arrays: refuse where it cannot fit rather than swap.
  const double sklearn_bytes = 6 * 8.0 * n * n;
  if (args.reference == "none") return {{"skipped", "--reference none"}};
  if (args.reference != "auto" && args.reference != "sklearn")
    fail("unknown --reference '", args.reference, "'; known: auto, sklearn, none");
  if (args.reference == "auto" && n > 12000)
    return {
        {"skipped", "scikit-learn needs about " + std::to_string(sklearn_bytes / 1e9) +
                        " GB at this size (six n×n float64 arrays); run with --reference sklearn to force"}};
  namespace fs = std::filesystem;
  fs::path dir = fs::temp_directory_path() / ("cshapes-bench-smacof-" + std::to_string(::getpid()));
  fs::create_directories(dir);
  struct Cleanup {
    fs::path dir;
    ~Cleanup() {
      std::error_code ec;
      fs::remove_all(dir, ec);
    }
  } cleanup{dir};
  {
    std::ofstream d(dir / "D.f32", std::ios::binary);
    d.write(reinterpret_cast<const char*>(D.data()), static_cast<std::streamsize>(sizeof(float) * n * n));
    Eigen::Matrix<double, Eigen::Dynamic, 3, Eigen::RowMajor> rows = X0;
    std::ofstream x(dir / "X0.f64", std::ios::binary);
    x.write(reinterpret_cast<const char*>(rows.data()), static_cast<std::streamsize>(sizeof(double) * n * 3));
    if (!d || !x) fail("bench smacof: cannot write the reference's input files in ", dir.string());
  }
  std::ofstream(dir / "run.py") << R"(import json, sys, time
import numpy as np
import sklearn
from sklearn.manifold import smacof
n, iters, folder = int(sys.argv[1]), int(sys.argv[2]), sys.argv[3]
D = np.fromfile(folder + "/D.f32", dtype=np.float32).reshape(n, n).astype(np.float64)
X0 = np.fromfile(folder + "/X0.f64", dtype=np.float64).reshape(n, 3)
kw = dict(metric=True, n_components=3, init=X0, n_init=1, max_iter=iters, eps=1e-300, return_n_iter=True)
if "normalized_stress" in smacof.__code__.co_varnames:
    kw["normalized_stress"] = False
start, cpu_start = time.perf_counter(), time.process_time()
X, stress, n_iter = smacof(D, **kw)
seconds, cpu = time.perf_counter() - start, time.process_time() - cpu_start
print(json.dumps({"version": sklearn.__version__, "seconds": seconds, "n_iter": int(n_iter),
                  "seconds_per_iteration": seconds / int(n_iter),
                  "cpu_seconds_per_iteration": cpu / int(n_iter), "stress": float(stress)}))
)";
  std::string command = "'" + args.python + "' '" + (dir / "run.py").string() + "' " + std::to_string(n) +
                        " " + std::to_string(iterations) + " '" + dir.string() + "' 2>'" +
                        (dir / "err").string() + "'";
  FILE* pipe = popen(command.c_str(), "r");
  if (!pipe) return {{"skipped", "cannot start " + args.python}};
  std::string output;
  char buffer[4096];
  while (size_t got = fread(buffer, 1, sizeof buffer, pipe)) output.append(buffer, got);
  int status = pclose(pipe);
  if (status != 0 || output.empty()) {
    std::ifstream err(dir / "err");
    std::string last, line;
    while (std::getline(err, line))
      if (!line.empty()) last = line;
    return {{"skipped", args.python + " with scikit-learn failed: " + last}};
  }
  return nlohmann::json::parse(output);
}

nlohmann::json acceleration_comparison(const DistanceMatrix& D, const Points& X0) {
  nlohmann::json out;
  SmacofOptions plain;
  plain.max_iterations = args.max_iterations;
  plain.tolerance = args.tolerance;
  plain.extrapolation_window = args.window;
  SmacofResult p = smacof(D, X0, plain);
  out["none"] = {{"iterations", p.iterations},
                 {"normalized_stress", p.normalized_stress},
                 {"stop_reason", p.stop_reason},
                 {"seconds", p.seconds}};
  for (SmacofAcceleration method : {SmacofAcceleration::Rre, SmacofAcceleration::Mpe}) {
    SmacofOptions fast = plain;
    fast.acceleration = method;
    fast.tolerance = 0;
    fast.target_stress = p.normalized_stress;
    SmacofResult a = smacof(D, X0, fast);
    out[to_string(method)] = {
        {"iterations", a.iterations},
        {"normalized_stress", a.normalized_stress},
        {"stop_reason", a.stop_reason},
        {"extrapolations_accepted", a.extrapolations_accepted},
        {"extrapolations_rejected", a.extrapolations_rejected},
        {"seconds", a.seconds},
        {"iteration_ratio", static_cast<double>(p.iterations) / std::max(1, a.iterations)}};
  }
  return out;
}

int run() {
  DistanceMatrix D;
  Points X0;  // the start both implementations get
  std::string source;
  if (!args.distances.empty()) {
    D = read_distance_matrix(args.distances);
    source = args.distances;
  } else if (!args.mesh.empty()) {
    Mesh mesh = read_mesh(args.mesh);
    std::string dropped;
    Submesh sub = require_connected(mesh, args.mesh, false, &dropped);
    GeodesicOptions go;
    go.method = parse_geodesic_method(args.geodesics);
    go.progress = progress_printer();
    D = all_pairs_geodesics(sub.mesh, go);
    X0 = sub.mesh.V;
    source = args.mesh + " (" + to_string(go.method) + " geodesics)";
  } else {
    CSHAPES_REQUIRE(args.n >= 4, "bench smacof: --n must be at least 4");
    const SwissRollSample roll = random_swiss_roll_points(args.n, args.seed);
    D = swiss_roll_geodesic_distances(roll);
    X0 = roll.X;
    source = "swiss roll, exact geodesics of " + std::to_string(args.n) + " uniform samples";
  }
  const Index n = D.rows();
  note("bench smacof: n = " + std::to_string(n) + ", " + source);

  ClassicalMdsResult cmds = classical_mds(D);
  note("classical MDS: " + std::to_string(cmds.seconds) + " s (" + std::to_string(cmds.matrix_products) +
       " products B·v)");
  if (X0.rows() == 0) X0 = cmds.X;

  SmacofOptions options;
  options.max_iterations = args.iterations;
  options.tolerance = 0;  // exactly `iterations` transforms, as the reference runs
  SmacofResult ours = smacof(D, X0, options);
  note("SMACOF: " + std::to_string(ours.seconds_per_iteration) + " s per iteration");
  // On a shared machine a second thread can cost more in synchronisation than it gains: measure one too.
  const int threads = omp_get_max_threads();
  SmacofResult single;
  if (threads > 1) {
    omp_set_num_threads(1);
    single = smacof(D, X0, options);
    omp_set_num_threads(threads);
    note("SMACOF, one thread: " + std::to_string(single.seconds_per_iteration) + " s per iteration");
  }

  nlohmann::json json;
  json["benchmark"] = "smacof";
  json["n"] = n;
  json["matrix"] = source;
  json["threads"] = threads;
  json["iterations"] = args.iterations;
  json["seconds_per_iteration"] = ours.seconds_per_iteration;
  json["cpu_seconds_per_iteration"] = ours.cpu_seconds_per_iteration;
  json["normalized_stress_start"] = ours.stress_history.front();
  json["normalized_stress_end"] = ours.normalized_stress;
  json["classical_mds"] = {{"seconds", cmds.seconds},
                           {"matrix_products", cmds.matrix_products},
                           {"eigenvalues", {cmds.eigenvalues[0], cmds.eigenvalues[1], cmds.eigenvalues[2]}},
                           {"most_negative_eigenvalue", cmds.most_negative_eigenvalue},
                           {"explained_energy", cmds.explained_energy}};
  if (n == 3505) json["paper_seconds_per_iteration"] = 1.59;
  if (n == 22738) json["paper_seconds_per_iteration"] = 277.5;

  nlohmann::json reference = sklearn_reference(D, X0, args.iterations);
  json["reference"] = reference;
  json["reference"]["name"] = "sklearn.manifold.smacof";
  if (reference.contains("seconds_per_iteration")) {
    const double ratio = reference["seconds_per_iteration"].get<double>() / ours.seconds_per_iteration;
    json["speedup_vs_reference"] = ratio;
    json["cpu_speedup_vs_reference"] =
        reference["cpu_seconds_per_iteration"].get<double>() / ours.cpu_seconds_per_iteration;
    // sklearn reports σ of the configuration before its last transform: our history entry iterations − 1.
    const int k = reference["n_iter"].get<int>() - 1;
    if (k >= 0 && k < static_cast<int>(ours.stress_history.size())) {
      double energy = 0;  // Σ_{i<j} δ², to unnormalise our history
      for (Index j = 0; j < n; ++j)
        for (Index i = 0; i < j; ++i) energy += static_cast<double>(D(i, j)) * D(i, j);
      json["reference"]["stress_relative_difference"] =
          std::abs(reference["stress"].get<double>() - ours.stress_history[k] * energy) /
          (ours.stress_history[k] * energy);
    }
    if (threads > 1)
      json["single_thread"] = {
          {"seconds_per_iteration", single.seconds_per_iteration},
          {"cpu_seconds_per_iteration", single.cpu_seconds_per_iteration},
          {"speedup_vs_reference",
           reference["seconds_per_iteration"].get<double>() / single.seconds_per_iteration},
          {"cpu_speedup_vs_reference",
           reference["cpu_seconds_per_iteration"].get<double>() / single.cpu_seconds_per_iteration}};
    note("scikit-learn: " + std::to_string(reference["seconds_per_iteration"].get<double>()) +
         " s per iteration; cshapes is " + std::to_string(ratio) + "x faster");
  } else {
    note("scikit-learn reference skipped: " + reference.value("skipped", std::string("?")));
    if (threads > 1)
      json["single_thread"] = {{"seconds_per_iteration", single.seconds_per_iteration},
                               {"cpu_seconds_per_iteration", single.cpu_seconds_per_iteration}};
  }
  if (args.acceleration) json["acceleration"] = acceleration_comparison(D, cmds.X);
  json["peak_rss_mb"] = peak_rss_mb();
  if (args.json) std::cout << json.dump(2) << std::endl;
  return 0;
}

const bool registered = register_command(
    {{"bench", "smacof"},
     "SMACOF seconds per iteration vs scikit-learn on the same geodesic distance matrix",
     [](CLI::App& app) {
       app.add_option("--n", args.n, "points of the generated Swiss-roll geodesic matrix")
           ->capture_default_str();
       app.add_option("--mesh", args.mesh,
                      "use the all-pairs geodesics of this mesh instead (start: the mesh)");
       app.add_option("--geodesics", args.geodesics, "geodesic method for --mesh")->capture_default_str();
       app.add_option("--distances", args.distances, "use this distance matrix (.bin) instead (start: cmds)");
       app.add_option("--iters", args.iterations, "timed iterations")->capture_default_str();
       app.add_option("--reference", args.reference, "auto (sklearn when it fits), sklearn or none")
           ->capture_default_str();
       app.add_option("--python", args.python, "interpreter with scikit-learn")->capture_default_str();
       app.add_flag("--acceleration", args.acceleration,
                    "also count iterations of plain, RRE and MPE SMACOF to the same stress (from cmds)");
       app.add_option("--tolerance", args.tolerance, "--acceleration: plain SMACOF's stopping tolerance")
           ->capture_default_str();
       app.add_option("--max-iters", args.max_iterations, "--acceleration: iteration cap")
           ->capture_default_str();
       app.add_option("--window", args.window, "--acceleration: Guttman steps per extrapolation")
           ->capture_default_str();
       app.add_option("--seed", args.seed, "random seed of the generated samples")->capture_default_str();
       app.add_flag("--json", args.json, "print the results as JSON on stdout");
     },
     run});

}  // namespace
}  // namespace cshapes::cli
