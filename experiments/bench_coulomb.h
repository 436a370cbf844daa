// The Coulomb gradient benchmark (`cshapes bench coulomb`): seconds per evaluation of the Coulomb energy and
// gradient of n points, fast multipole (canon/coulomb_fmm.h) vs direct summation (canon/coulomb_energy.h),
// and the fast method's relative L2 errors against direct summation, measured in one run.
//
// Points: a mesh's vertices (mesh given, n 0 or its vertex count), n points on its surface (mesh and another
// n), or n random points of a distribution (data/synthetic.h random_points), drawn from `seed`.
//
// The fast sum is timed over `fast_repeats` runs after an untimed one (an evaluation takes milliseconds: one
// descheduled thread moves a single run by tens of percent). Up to full_direct_max points the direct sum is
// complete (`repeats` runs in double and in float, taking turns with the fast runs in as many rounds) and the
// errors are over all points; above it the exact sum runs once on a random sample of `sample` distinct
// targets, the errors are over those targets (the energy error from their potentials), and
// direct_seconds is the sample's time scaled by n / sample (direct_extrapolated). Wall and process CPU
// seconds are medians by support/timing.h's rule; on a shared machine the CPU seconds show the work done
// independently of the share of the cores obtained.
#pragma once

#include <nlohmann/json.hpp>
#include <string>

#include "cshapes/canon/coulomb_fmm.h"
#include "cshapes/data/synthetic.h"

namespace cshapes {

struct CoulombBenchOptions {
  Index n = 0;  // points (with mesh: sampled on its surface; 0 or its vertex count: its vertices)
  PointDistribution distribution = PointDistribution::Uniform;  // without mesh
  std::string mesh;                                             // mesh file; "": random points
  int repeats = 5;                // timed runs of the direct sums (median reported), >= 1
  int fast_repeats = 25;          // timed runs of the fast sum (median reported), >= 1
  double accuracy = 1e-3;         // fast summation's target relative L2 gradient error
  int order = 0;                  // expansion order override (0: from accuracy)
  double opening_angle = 0;       // opening angle override (0: from accuracy)
  int leaf_size = 0;              // leaf size override (0: from accuracy)
  Index sample = 1000;            // error targets when the full direct sum is skipped
  Index full_direct_max = 50000;  // largest n summed completely by direct summation
  unsigned seed = 1;              // points and the error sample
};

struct CoulombBenchResult {
  CoulombBenchOptions options;  // as run
  Index n = 0;
  std::string distribution;                       // "uniform", or "mesh-vertices:PATH", "mesh-surface:PATH"
  int threads = 0;                                // OpenMP threads available
  double fast_seconds = 0, fast_cpu_seconds = 0;  // FMM, medians
  double direct_seconds = 0, direct_cpu_seconds = 0;  // direct (double), medians or extrapolated
  bool direct_extrapolated = false;                   // from `error_targets` sampled targets
  bool direct_float_measured = false;                 // the float direct sum (complete sums only)
  double direct_float_seconds = 0, direct_float_cpu_seconds = 0;
  double gradient_rel_error = 0;  // ‖g_fast − g_direct‖ / ‖g_direct‖ over the error targets
  double energy_rel_error = 0;  // |E_fast − E_direct| / |E_direct| (sampled: of Σ_t φ_t over the targets)
  Index error_targets = 0;      // n, or the sample's size
  CoulombFmmStats stats;        // of the last fast run, each phase the median over the timed runs
  // direct / fast (wall seconds)
  double speedup() const { return direct_seconds / fast_seconds; }
  double speedup_vs_direct_float() const { return direct_float_seconds / fast_seconds; }
};

CoulombBenchResult bench_coulomb(const CoulombBenchOptions& options);

// {n, distribution, direct_seconds, direct_extrapolated, fast_seconds, direct_cpu_seconds, fast_cpu_seconds,
//  speedup, gradient_rel_error, energy_rel_error, error_targets, threads, accuracy, order, opening_angle,
//  leaf_size, repeats, fast_repeats, cells, m2l_interactions, p2p_interactions, fast_phase_seconds: {tree, upward,
//  traversal, interactions (with the downward pass), m2l_thread_seconds, p2p_thread_seconds}} and, for a
//  complete direct sum, direct_float_seconds, direct_float_cpu_seconds, speedup_vs_direct_float.
nlohmann::json to_json(const CoulombBenchResult& result);

}  // namespace cshapes
