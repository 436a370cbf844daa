#include "cshapes/experiments/bench_smacof.h"

#include <omp.h>

#include <algorithm>
#include <cmath>
#include <fstream>

#include "cshapes/canon/classical_mds.h"
#include "cshapes/canon/smacof.h"
#include "cshapes/support/distance_matrix.h"
#include "cshapes/support/error.h"
#include "cshapes/support/format.h"
#include "cshapes/support/timing.h"
#include "cshapes/mesh/io.h"
#include "cshapes/data/synthetic.h"
#include "cshapes/experiments/bench_support.h"

namespace cshapes {

namespace {

// scikit-learn's smacof on D (D.f32, n×n float32) from X0 (X0.f64, n×3 row-major float64) in the folder given
// as its first argument: exactly `iterations` transforms, timed inside Python; prints one JSON object.
const char* const kSklearnScript = R"(import json, sys, time
import numpy as np
import sklearn
from sklearn.manifold import smacof
folder, n, iters = sys.argv[1], int(sys.argv[2]), int(sys.argv[3])
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

// Fills the reference fields of `result` (or reference_skipped).
void measure_sklearn(const DistanceMatrix& D, const Points& X0, SmacofBenchResult& result) {
  const SmacofBenchOptions& options = result.options;
  const Index n = D.rows();
  // sklearn holds D and several n×n float64 work arrays: refuse where it cannot fit rather than swap.
  const double sklearn_bytes = 6 * 8.0 * n * n;
  if (options.reference == SmacofBenchReference::None) {
    result.reference_skipped = "not asked for (--reference none)";
    return;
  }
  if (options.reference == SmacofBenchReference::Auto && n > 12000) {
    result.reference_skipped =
        "scikit-learn needs about " + significant(sklearn_bytes / 1e9) +
        " GB at this size (six n×n float64 arrays); run with --reference sklearn to force";
    return;
  }
  AnchorScript script;
  script.package = "scikit-learn";
  script.imports = "numpy, sklearn.manifold";
  script.python = options.python;
  script.source = kSklearnScript;
  script.arguments = {std::to_string(n), std::to_string(options.iterations)};
  script.write_inputs = [&](const std::string& folder) {
    std::ofstream d(folder + "/D.f32", std::ios::binary);
    d.write(reinterpret_cast<const char*>(D.data()), static_cast<std::streamsize>(sizeof(float) * n * n));
    const Eigen::Matrix<double, Eigen::Dynamic, 3, Eigen::RowMajor> rows = X0;
    std::ofstream x(folder + "/X0.f64", std::ios::binary);
    x.write(reinterpret_cast<const char*>(rows.data()), static_cast<std::streamsize>(sizeof(double) * n * 3));
    if (!d || !x) fail_write("bench smacof: cannot write the reference's input files in ", folder);
  };
  const AnchorRun run = run_python_anchor(script);
  if (!run.ran) {
    result.reference_skipped = run.skipped;
    return;
  }
  const nlohmann::json reference = nlohmann::json::parse(run.output, nullptr, /*allow_exceptions=*/false);
  if (!reference.is_object() || !reference.contains("seconds_per_iteration")) {
    result.reference_skipped = "unexpected output from the scikit-learn script: " + run.output;
    return;
  }
  result.reference_measured = true;
  result.reference_version = reference.at("version").get<std::string>();
  result.reference_seconds = reference.at("seconds").get<double>();
  result.reference_iterations = reference.at("n_iter").get<int>();
  result.reference_seconds_per_iteration = reference.at("seconds_per_iteration").get<double>();
  result.reference_cpu_seconds_per_iteration = reference.at("cpu_seconds_per_iteration").get<double>();
  result.reference_stress = reference.at("stress").get<double>();
}

SmacofBenchRun summary(const SmacofResult& r) {
  return {
      r.iterations, r.normalized_stress, r.stop_reason, r.extrapolations_accepted, r.extrapolations_rejected,
      r.seconds};
}

// Plain SMACOF to its tolerance, then RRE and MPE to the stress plain reached.
void compare_acceleration(const DistanceMatrix& D, const Points& X0, SmacofBenchResult& result) {
  SmacofOptions plain;
  plain.max_iterations = result.options.max_iterations;
  plain.tolerance = result.options.tolerance;
  plain.extrapolation_window = result.options.window;
  result.plain = summary(smacof(D, X0, plain));
  for (SmacofAcceleration method : {SmacofAcceleration::Rre, SmacofAcceleration::Mpe}) {
    SmacofOptions fast = plain;
    fast.acceleration = method;
    fast.tolerance = 0;
    fast.target_stress = result.plain.normalized_stress;
    (method == SmacofAcceleration::Rre ? result.rre : result.mpe) = summary(smacof(D, X0, fast));
  }
  result.acceleration_measured = true;
}

// Ours again on one OpenMP thread (when there are more).
void time_one_thread(const DistanceMatrix& D, const Points& X0, const SmacofOptions& options,
                     SmacofBenchResult& result) {
  const int threads = omp_get_max_threads();
  result.threads = threads;
  if (threads <= 1) return;
  omp_set_num_threads(1);
  const SmacofResult single = smacof(D, X0, options);
  omp_set_num_threads(threads);
  result.single_thread_measured = true;
  result.single_thread_seconds_per_iteration = single.seconds_per_iteration;
  result.single_thread_cpu_seconds_per_iteration = single.cpu_seconds_per_iteration;
  result.options.notes.say("SMACOF, one thread: " + seconds_text(single.seconds_per_iteration) +
                           " per iteration");
}

// The relative difference of scikit-learn's stress and ours after as many transforms. sklearn reports σ of
// the configuration before its last transform: our history entry iterations − 1.
void compare_stress(const DistanceMatrix& D, const SmacofResult& ours, SmacofBenchResult& result) {
  const int k = result.reference_iterations - 1;
  if (k < 0 || k >= static_cast<int>(ours.stress_history.size())) return;
  double energy = 0;  // Σ_{i<j} δ², to unnormalise our history
  for (Index j = 0; j < D.rows(); ++j)
    for (Index i = 0; i < j; ++i) energy += static_cast<double>(D(i, j)) * D(i, j);
  result.reference_stress_relative_difference =
      std::abs(result.reference_stress - ours.stress_history[k] * energy) / (ours.stress_history[k] * energy);
}

}  // namespace

SmacofBenchResult bench_smacof(const SmacofBenchOptions& options) {
  CSHAPES_REQUIRE(options.rounds >= 1, "bench smacof: --rounds must be at least 1, got ", options.rounds);
  SmacofBenchResult result;
  result.options = options;
  const Notes& notes = options.notes;
  DistanceMatrix D;
  Points X0;  // the start both implementations get
  if (!options.distances.empty()) {
    D = read_distance_matrix(options.distances);
    result.matrix = options.distances;
  } else if (!options.mesh.empty()) {
    Mesh mesh = read_mesh(options.mesh);
    std::string dropped;
    Submesh sub = require_connected(mesh, options.mesh, false, &dropped);
    GeodesicOptions go;
    go.method = options.geodesics;
    go.progress = notes.progress;
    D = all_pairs_geodesics(sub.mesh, go);
    X0 = sub.mesh.V;
    result.matrix = options.mesh + " (" + to_string(go.method) + " geodesics)";
  } else {
    CSHAPES_REQUIRE(options.n >= 4, "bench smacof: --points must be at least 4");
    const SwissRollSample roll = random_swiss_roll_points(options.n, options.seed);
    D = swiss_roll_geodesic_distances(roll);
    X0 = roll.X;
    result.matrix = "swiss roll, exact geodesics of " + std::to_string(options.n) + " uniform samples";
  }
  const Index n = D.rows();
  result.n = n;
  notes.say("bench smacof: n = " + std::to_string(n) + ", " + result.matrix);

  const ClassicalMdsResult cmds = classical_mds(D);
  result.cmds_seconds = cmds.seconds;
  result.cmds_matrix_products = cmds.matrix_products;
  result.cmds_eigenvalues = cmds.eigenvalues;
  result.cmds_most_negative_eigenvalue = cmds.most_negative_eigenvalue;
  result.cmds_explained_energy = cmds.explained_energy;
  notes.say("classical MDS: " + seconds_text(cmds.seconds) + " (" + std::to_string(cmds.matrix_products) +
            " products B·v)");
  if (X0.rows() == 0) X0 = cmds.X;

  SmacofOptions smacof_options;
  smacof_options.max_iterations = options.iterations;
  smacof_options.tolerance = 0;  // exactly `iterations` transforms, as the reference runs
  // Ours and the reference take turns, `rounds` times; each side's figure is the median of its rounds, so
  // that a slow spell of a shared machine (seconds long; the reference's own time varied by half between
  // runs) moves neither the figure nor the ratio much.
  SmacofResult ours;
  std::vector<double> ours_wall, ours_cpu, reference_wall, reference_cpu, reference_seconds;
  bool try_reference = true;
  auto reference_round = [&] {
    measure_sklearn(D, X0, result);
    if (!result.reference_measured) {
      try_reference = false;
      return;
    }
    reference_wall.push_back(result.reference_seconds_per_iteration);
    reference_cpu.push_back(result.reference_cpu_seconds_per_iteration);
    reference_seconds.push_back(result.reference_seconds);
  };
  for (int round = 0; round < options.rounds; ++round) {
    ours = smacof(D, X0, smacof_options);
    ours_wall.push_back(ours.seconds_per_iteration);
    ours_cpu.push_back(ours.cpu_seconds_per_iteration);
    // The last round's reference runs after the one-thread timing below.
    if (round + 1 < options.rounds && try_reference) reference_round();
  }
  result.rounds = static_cast<int>(ours_wall.size());
  result.seconds_per_iteration = median(ours_wall);
  result.cpu_seconds_per_iteration = median(ours_cpu);
  result.normalized_stress_start = ours.stress_history.front();
  result.normalized_stress_end = ours.normalized_stress;
  notes.say("SMACOF: " + seconds_text(result.seconds_per_iteration) + " per iteration (median of " +
            std::to_string(result.rounds) + " rounds)");
  time_one_thread(D, X0, smacof_options, result);
  if (n == 3505) result.paper_seconds_per_iteration = 1.59;
  if (n == 22738) result.paper_seconds_per_iteration = 277.5;

  if (try_reference) reference_round();
  if (result.reference_measured) {
    result.reference_rounds = static_cast<int>(reference_wall.size());
    result.reference_seconds_per_iteration = median(reference_wall);
    result.reference_cpu_seconds_per_iteration = median(reference_cpu);
    result.reference_seconds = median(reference_seconds);
    compare_stress(D, ours, result);
    notes.say("scikit-learn: " + seconds_text(result.reference_seconds_per_iteration) +
              " per iteration; cshapes is " + significant(result.speedup_vs_reference()) + "x faster");
  } else {
    notes.say("scikit-learn reference skipped: " + result.reference_skipped);
  }
  if (options.acceleration) compare_acceleration(D, cmds.X, result);
  result.peak_rss_mb = peak_rss_mb();
  return result;
}

namespace {

nlohmann::json run_json(const SmacofBenchRun& run) {
  return {{"iterations", run.iterations},
          {"normalized_stress", run.normalized_stress},
          {"stop_reason", run.stop_reason},
          {"seconds", run.seconds}};
}

nlohmann::json accelerated_run_json(const SmacofBenchRun& run, const SmacofBenchRun& plain) {
  nlohmann::json j = run_json(run);
  j["extrapolations_accepted"] = run.extrapolations_accepted;
  j["extrapolations_rejected"] = run.extrapolations_rejected;
  j["iteration_ratio"] = static_cast<double>(plain.iterations) / std::max(1, run.iterations);
  return j;
}

}  // namespace

nlohmann::json to_json(const SmacofBenchResult& r) {
  nlohmann::json json;
  json["benchmark"] = "smacof";
  json["n"] = r.n;
  json["matrix"] = r.matrix;
  json["threads"] = r.threads;
  json["iterations"] = r.options.iterations;
  json["rounds"] = r.rounds;
  json["seconds_per_iteration"] = r.seconds_per_iteration;
  json["cpu_seconds_per_iteration"] = r.cpu_seconds_per_iteration;
  json["normalized_stress_start"] = r.normalized_stress_start;
  json["normalized_stress_end"] = r.normalized_stress_end;
  json["classical_mds"] = {
      {"seconds", r.cmds_seconds},
      {"matrix_products", r.cmds_matrix_products},
      {"eigenvalues", {r.cmds_eigenvalues[0], r.cmds_eigenvalues[1], r.cmds_eigenvalues[2]}},
      {"most_negative_eigenvalue", r.cmds_most_negative_eigenvalue},
      {"explained_energy", r.cmds_explained_energy}};
  if (r.paper_seconds_per_iteration > 0) json["paper_seconds_per_iteration"] = r.paper_seconds_per_iteration;
  nlohmann::json& reference = json["reference"];
  reference["name"] = "sklearn.manifold.smacof";
  nlohmann::json single = {{"seconds_per_iteration", r.single_thread_seconds_per_iteration},
                           {"cpu_seconds_per_iteration", r.single_thread_cpu_seconds_per_iteration}};
  if (r.reference_measured) {
    reference["version"] = r.reference_version;
    reference["rounds"] = r.reference_rounds;
    reference["seconds"] = r.reference_seconds;
    reference["n_iter"] = r.reference_iterations;
    reference["seconds_per_iteration"] = r.reference_seconds_per_iteration;
    reference["cpu_seconds_per_iteration"] = r.reference_cpu_seconds_per_iteration;
    reference["stress"] = r.reference_stress;
    if (r.reference_stress_relative_difference >= 0)
      reference["stress_relative_difference"] = r.reference_stress_relative_difference;
    json["speedup_vs_reference"] = r.speedup_vs_reference();
    json["cpu_speedup_vs_reference"] = r.cpu_speedup_vs_reference();
    single["speedup_vs_reference"] =
        r.reference_seconds_per_iteration / r.single_thread_seconds_per_iteration;
    single["cpu_speedup_vs_reference"] =
        r.reference_cpu_seconds_per_iteration / r.single_thread_cpu_seconds_per_iteration;
  } else {
    reference["skipped"] = r.reference_skipped;
  }
  if (r.single_thread_measured) json["single_thread"] = single;
  if (r.acceleration_measured)
    json["acceleration"] = {{"none", run_json(r.plain)},
                            {to_string(SmacofAcceleration::Rre), accelerated_run_json(r.rre, r.plain)},
                            {to_string(SmacofAcceleration::Mpe), accelerated_run_json(r.mpe, r.plain)}};
  json["peak_rss_mb"] = r.peak_rss_mb;
  json["build"] = build_json();
  return json;
}

}  // namespace cshapes
