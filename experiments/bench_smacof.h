// The SMACOF benchmark (`cshapes bench smacof`): seconds per SMACOF iteration (canon/smacof.h) on an n×n
// geodesic distance matrix, beside scikit-learn's sklearn.manifold.smacof on the same matrix and start (run
// by the interpreter that imports numpy and scikit-learn: experiments/figures.h find_python); also classical
// MDS time (canon/classical_mds.h), peak memory and, with acceleration, the passes RRE and MPE need to reach
// the plain iteration's stress.
//
// The matrix: a distance file, the all-pairs geodesics of a mesh (start: the mesh; only one connected
// component is accepted), or, by default, n points drawn uniformly on the unrolled Swiss roll (the paper's
// swissroll scaled to n; start: those points), whose geodesic distances are exactly the Euclidean distances
// in the flat unrolled rectangle. Without a start of its own (a distance file) both implementations start
// from classical MDS. Exactly `iterations` Guttman transforms are timed on each side (tolerance 0, eps
// 1e-300), in `rounds` rounds where the two sides take turns, each side's figure the median of its rounds;
// with more than one OpenMP thread ours is timed on one thread too (on a shared machine a second
// thread can cost more in synchronisation than it gains).
//
// The reference is skipped, with the reason, when asked (reference None), when scikit-learn would need more
// than about 6 n×n float64 arrays at n > 12,000 (reference Auto; Sklearn forces it), or when no interpreter
// runs it.
#pragma once

#include <nlohmann/json.hpp>
#include <string>

#include "cshapes/geodesics/geodesics.h"
#include "cshapes/pipeline/experiment_kit.h"

namespace cshapes {

enum class SmacofBenchReference {
  Auto,     // scikit-learn when it fits (n ≤ 12,000)
  Sklearn,  // scikit-learn at any size
  None,     // no reference
};

struct SmacofBenchOptions {
  Index n = 3505;    // points of the generated Swiss-roll geodesic matrix, >= 4
  std::string mesh;  // or: the all-pairs geodesics of this mesh (start: the mesh)
  GeodesicMethod geodesics = GeodesicMethod::FastMarching;  // for mesh
  std::string distances;  // or: this distance matrix file (start: classical MDS)
  int iterations = 10;    // timed iterations, on both sides
  int rounds = 3;         // ours and the reference take turns this many times (medians reported), >= 1
  SmacofBenchReference reference = SmacofBenchReference::Auto;
  std::string python;  // interpreter with scikit-learn; "": the first that imports numpy and sklearn
  bool acceleration =
      false;  // also count the passes of plain, RRE and MPE SMACOF to the same stress (from cmds)
  double tolerance = 1e-5;    // acceleration: plain SMACOF's stopping tolerance
  int max_iterations = 1000;  // acceleration: iteration cap
  int window = 6;             // acceleration: Guttman steps per extrapolation
  unsigned seed = 1;          // the Swiss-roll samples
  Notes notes;                // the geodesics' progress; a line per stage measured
};

// One SMACOF run to a stress (the acceleration comparison).
struct SmacofBenchRun {
  int iterations = 0;  // passes over D
  double normalized_stress = 0;
  std::string stop_reason;
  int extrapolations_accepted = 0, extrapolations_rejected = 0;
  double seconds = 0;  // wall
};

struct SmacofBenchResult {
  SmacofBenchOptions options;  // as run
  Index n = 0;
  std::string matrix;                                               // where the distances came from, in words
  int threads = 0;                                                  // OpenMP threads of our timing
  int rounds = 0;                                                   // our timed runs
  double seconds_per_iteration = 0, cpu_seconds_per_iteration = 0;  // ours (canon/smacof.h's own clocks)
  double normalized_stress_start = 0, normalized_stress_end = 0;
  bool single_thread_measured = false;  // threads > 1: ours again on one thread
  double single_thread_seconds_per_iteration = 0, single_thread_cpu_seconds_per_iteration = 0;
  // Classical MDS of the same matrix (also the start of a distance file and of the acceleration runs).
  double cmds_seconds = 0;
  int cmds_matrix_products = 0;  // products B·v of the Lanczos iteration
  Eigen::Vector3d cmds_eigenvalues = Eigen::Vector3d::Zero();
  double cmds_most_negative_eigenvalue = 0, cmds_explained_energy = 0;
  double paper_seconds_per_iteration = 0;  // the paper's Table 1 at n = 3,505 and 22,738, else 0
  // scikit-learn, when measured (reference_skipped empty).
  bool reference_measured = false;
  std::string reference_skipped;  // why not measured
  std::string reference_version;
  double reference_seconds = 0, reference_seconds_per_iteration = 0, reference_cpu_seconds_per_iteration = 0;
  int reference_iterations = 0;
  int reference_rounds = 0;  // runs of the reference (its figures: their medians)
  double reference_stress = 0;  // σ before sklearn's last transform, unnormalised
  // |σ_sklearn − σ_ours| / σ_ours at the same configuration (our history unnormalised); < 0 when not
  // compared.
  double reference_stress_relative_difference = -1;
  bool acceleration_measured = false;
  SmacofBenchRun plain, rre, mpe;  // with acceleration: plain to its tolerance, RRE and MPE to plain's stress
  double peak_rss_mb = 0;          // of the process, at the end
  double speedup_vs_reference() const { return reference_seconds_per_iteration / seconds_per_iteration; }
  double cpu_speedup_vs_reference() const {
    return reference_cpu_seconds_per_iteration / cpu_seconds_per_iteration;
  }
};

SmacofBenchResult bench_smacof(const SmacofBenchOptions& options);

// {benchmark: "smacof", n, matrix, threads, iterations, rounds, seconds_per_iteration,
//  cpu_seconds_per_iteration, normalized_stress_start, normalized_stress_end, classical_mds: {seconds, matrix_products, eigenvalues,
//  most_negative_eigenvalue, explained_energy}, paper_seconds_per_iteration (at the paper's sizes),
//  reference: {name, and skipped | version, rounds, seconds, n_iter, seconds_per_iteration,
//  cpu_seconds_per_iteration, stress, stress_relative_difference}, speedup_vs_reference and
//  cpu_speedup_vs_reference (when measured), single_thread: {seconds_per_iteration,
//  cpu_seconds_per_iteration, and with the reference speedup_vs_reference, cpu_speedup_vs_reference} (threads
//  > 1), acceleration: {none, rre, mpe} (when asked), peak_rss_mb}.
nlohmann::json to_json(const SmacofBenchResult& result);

}  // namespace cshapes
