// The Coulomb iteration benchmark (`cshapes bench coulomb-iteration`): seconds of one outer iteration of the
// Coulomb canonization (1 Coulomb step + 1 projection sweep, the setting of the paper's Table 1), the median
// over `repeats` iterations of the real loop (experiments/timing_table.h coulomb_iteration_seconds), against
// the paper's figures: 0.045 s at 3,505 vertices and 0.21 s at 22,738, interpolated log-log in n
// (extrapolated outside). Timed with the canonization's defaults (fast sum at 1e-2 in the iterations) and
// again with the fast sum at 1e-3, in `windows` windows each (a fresh run of `repeats` timed iterations),
// the two settings taking turns after one untimed window of each: the figure is the median of the windows'
// medians, and every window's median is kept, so a few seconds of a slower machine move one window, not the
// figure, and the spread is seen.
#pragma once

#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "cshapes/support/types.h"

namespace cshapes {

struct CoulombIterationBenchOptions {
  std::string mesh;  // mesh file (with faces); "": a torus of about n vertices
  int n = 3505;      // vertices of the generated torus, >= 16
  int repeats = 50;  // iterations timed per window (median), >= 1
  int windows = 5;   // windows per setting (median of their medians reported), >= 1
  // The fast summation's tree kept for this many iterations (CoulombCanonOptions::fmm_rebuild_every); 0: the
  // canonization's default. Above 1 a window's figure is the median of its cycles' means (each cycle holds
  // one rebuild).
  int fmm_rebuild_every = 0;
};

struct CoulombIterationBenchResult {
  CoulombIterationBenchOptions options;  // as run
  std::string source;                    // the mesh file, or "torus NUxNV"
  Index vertices = 0, edges = 0;
  int threads = 0;                  // OpenMP threads available
  double seconds = 0;               // per iteration, median of the windows, the canonization's defaults
  double seconds_accuracy_1e3 = 0;  // per iteration, median of the windows, fast sum at 1e-3
  std::vector<double> window_seconds, window_seconds_accuracy_1e3;  // each window's median, in run order
  double paper_seconds = 0;         // the paper's Table 1 at this many vertices (power law, see above)
  double speedup_vs_paper() const { return paper_seconds / seconds; }
  double speedup_vs_paper_accuracy_1e3() const { return paper_seconds / seconds_accuracy_1e3; }
};

// The paper's Table 1 (Coulomb, one iteration) at n vertices: the power law through (3505, 0.045 s) and
// (22738, 0.21 s).
double paper_coulomb_iteration_seconds(double n);

CoulombIterationBenchResult bench_coulomb_iteration(const CoulombIterationBenchOptions& options);

// {benchmark: "coulomb-iteration", source, vertices, edges, repeats, windows, threads, seconds_per_iteration,
//  seconds_per_iteration_windows, paper_seconds_per_iteration, speedup_vs_paper,
//  seconds_per_iteration_accuracy_1e-3, seconds_per_iteration_accuracy_1e-3_windows,
//  speedup_vs_paper_accuracy_1e-3, goal_speedup: 30, note, build}.
nlohmann::json to_json(const CoulombIterationBenchResult& result);

}  // namespace cshapes
