// The all-pairs geodesics benchmark (`cshapes bench geodesics`): our block heat method (geodesics/heat_method.h,
// as `cshapes geodesics --method heat` runs it) against the anchor, CGAL's Heat_method_3 solving one source
// at a time (the paper's baseline: 10.24 s at 3,505 vertices, 647.6 s at 22,738), with both methods' mean
// relative error against CGAL's exact geodesics on sampled sources. Fast marching is timed and scored beside
// them.
//
// Both sides run on the same threads: ours parallel over blocks of sources, the anchor with one CGAL solver
// per thread. The anchor is timed on anchor_samples random sources (all n when that many are asked for) and
// extrapolated to n: set-up (one factorisation per thread, concurrently) + n × seconds per source; fast
// marching likewise from fmm_samples sources (its set-up: the stencil precomputation). Wall-clock and process
// CPU seconds are both reported: on a shared machine the CPU-time ratio is the steadier one.
//
// Error: mean of |d − exact| / exact over the vertices farther than 3 mean edge lengths from the source,
// averaged over exact_samples random sources (near the source relative errors are meaningless).
#pragma once

#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "cshapes/geodesics/geodesics_cgal.h"
#include "cshapes/pipeline/experiment_kit.h"

namespace cshapes {

struct GeodesicsBenchOptions {
  int n = 0;         // a torus (R 2, r 0.7) refined to exactly n vertices; or (exclusive) mesh:
  std::string mesh;  // mesh file
  int vertices = 0;  // with mesh: refine it to exactly this many vertices (0: as it is)
  CgalHeatMode heat_mode = CgalHeatMode::IntrinsicDelaunay;  // for both heat methods
  int anchor_samples = 96;  // sources timed for CGAL's heat method (>= n: the full all-pairs run)
  int exact_samples = 4;    // sources with exact geodesics for the errors
  int fmm_samples = 256;    // sources timed for fast marching
  unsigned seed = 1;        // the sampled sources
  Notes notes;              // our all-pairs run's progress; one line on the mesh before the work
};

// One method's line: wall and CPU seconds for all n sources (measured or extrapolated), error vs exact.
struct GeodesicsBenchMethod {
  std::string method;          // what ran, in words
  double seconds = 0;          // wall
  double cpu_seconds = 0;      // process CPU (ours and the anchor)
  size_t sampled_sources = 0;  // the anchor and fast marching: sources timed
  double mean_relative_error = 0;
};

struct GeodesicsBenchResult {
  GeodesicsBenchOptions options;  // as run
  std::string mesh;               // what was measured, in words ("torus 42x14 (R 2, r 0.7), ...")
  Index vertices = 0, faces = 0;
  int threads = 0;  // OpenMP threads, for every method
  GeodesicsBenchMethod ours, anchor, fmm;
  bool anchor_extrapolated = false;  // anchor timed on fewer than n sources
  double anchor_setup_seconds = 0;   // wall, one factorisation per thread
  double anchor_seconds_per_source_per_thread = 0;
  std::vector<int> exact_sources;  // the error's sources
  double exact_seconds = 0;        // wall, exact geodesics and the errors
  double paper_seconds = 0;        // the paper's all-pairs time at this n (3,505, 22,738), else 0
  double speedup_vs_anchor() const { return anchor.seconds / ours.seconds; }
  double cpu_speedup_vs_anchor() const { return anchor.cpu_seconds / ours.cpu_seconds; }
};

GeodesicsBenchResult bench_geodesics(const GeodesicsBenchOptions& options);

// {benchmark: "all-pairs geodesics", mesh, vertices, faces, threads, heat_mode,
//  ours: {method, seconds, cpu_seconds, mean_relative_error_vs_exact},
//  anchor: {method, seconds, cpu_seconds, extrapolated, sampled_sources, setup_seconds,
//           seconds_per_source_per_thread, mean_relative_error_vs_exact, note (when extrapolated)},
//  fmm: {method, seconds, sampled_sources, mean_relative_error_vs_exact},
//  speedup_vs_anchor, cpu_speedup_vs_anchor, exact_sources, exact_seconds, error_measure, paper_seconds (at
//  the paper's sizes only)}.
nlohmann::json to_json(const GeodesicsBenchResult& result);

}  // namespace cshapes
