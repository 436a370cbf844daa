// The measurements behind the paper's Table 1: seconds of the pre-computation and of one iteration of the
// optimisation, for SMACOF MDS-based canonical forms and for Coulomb shapes, as medians of repeated runs.
//
//   MDS pre-computation      all-pairs geodesic distances (the method of GeodesicOptions)
//   MDS iteration            one SMACOF pass over the distance matrix (Guttman transform + stress)
//   Coulomb pre-computation  edge extraction and rest lengths (what the optimisation needs before it starts)
//   Coulomb iteration        one Coulomb step (eq. 4, summation auto) + one L2 projection sweep (eq. 6)
#pragma once

#include <string>
#include <vector>

#include "cshapes/geodesics/geodesics.h"
#include "cshapes/mesh/mesh.h"

namespace cshapes {

struct TimingOptions {
  int repeats = 5;            // timed runs per measurement (the median is reported)
  GeodesicOptions geodesics;  // MDS pre-computation
  bool mds = true;            // false: skip the MDS columns (e.g. when n² floats do not fit)
  // Each measurement's progress, as ("Table 1, <shape>: all-pairs geodesics" | "…: SMACOF passes" | "…:
  // Coulomb iterations", done, total); polls (an empty stage) pass through, so a stop is heard.
  ProgressFn progress;
};

struct TimingRow {
  std::string shape;
  Index vertices = 0;
  double mds_precompute = 0;      // seconds (a single run: all-pairs geodesics are the expensive part)
  double mds_iteration = 0;       // seconds, median
  double coulomb_precompute = 0;  // seconds, median
  double coulomb_iteration = 0;   // seconds, median
  bool mds_measured = false;
};

// Measures one row. The mesh must be one connected component. Progress through options.progress.
TimingRow time_canonical_forms(const std::string& shape, const Mesh& mesh, const TimingOptions& options = {});

// Seconds of one outer Coulomb iteration (1 gradient step + 1 projection sweep), median of `repeats`, with
// the canonization's default options otherwise; accuracy: the fast summation's target gradient error (0: the
// canonization's default, 1e-2; 1e-3 is the library-wide default of coulomb_energy_gradient).
// fmm_rebuild_every: the fast summation's tree kept for this many iterations (CoulombCanonOptions; 0: the
// canonization's default); above 1, the median of the means of consecutive runs of that many iterations, each
// of which holds one rebuild (the cost per iteration over a whole cycle).
double coulomb_iteration_seconds(const Mesh& mesh, int repeats, double accuracy = 0,
                                 int fmm_rebuild_every = 0, const ProgressFn& progress = {});

}  // namespace cshapes
