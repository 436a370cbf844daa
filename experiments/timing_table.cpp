#include "cshapes/experiments/timing_table.h"

#include <algorithm>
#include <numeric>

#include "cshapes/canon/coulomb.h"
#include "cshapes/canon/smacof.h"
#include "cshapes/support/error.h"
#include "cshapes/support/timing.h"

namespace cshapes {

double coulomb_iteration_seconds(const Mesh& mesh, int repeats, double accuracy, int fmm_rebuild_every,
                                 const ProgressFn& progress) {
  CSHAPES_REQUIRE(repeats >= 1, "timing: repeats must be >= 1");
  CoulombCanonOptions o;
  o.scheme = CoulombScheme::Paper;  // Table 1: a single Coulomb step and a single projection step
  o.step_rule = CoulombStepRule::MaxEdge;
  o.start = CoulombStart::Input;  // the paper's iteration, from the input
  o.flatten = 0;
  o.coulomb_steps = 1;
  o.projection.steps = 1;
  o.tear_fraction = 0;
  o.stop_tolerance = 0;
  o.max_iterations = repeats + 1;  // the first iteration warms caches and threads up
  if (accuracy > 0) o.energy.accuracy = accuracy;
  if (fmm_rebuild_every > 0) o.fmm_rebuild_every = fmm_rebuild_every;
  const int cycle = o.fmm_rebuild_every;
  if (cycle > 1) o.max_iterations = cycle * std::max(1, repeats / cycle) + 1;
  o.progress = progress;
  const CoulombCanonResult r = coulomb_canonical_form(mesh.V, mesh_edges(mesh.F), o);
  std::vector<double> per_iteration;
  for (size_t k = 1; k < r.history.size(); ++k)
    per_iteration.push_back(r.history[k].seconds - r.history[k - 1].seconds);
  if (cycle <= 1) return median(per_iteration);
  std::vector<double> cycle_means;
  for (size_t k = 0; k + cycle <= per_iteration.size(); k += cycle)
    cycle_means.push_back(
        std::accumulate(per_iteration.begin() + k, per_iteration.begin() + k + cycle, 0.0) / cycle);
  return median(cycle_means);
}

TimingRow time_canonical_forms(const std::string& shape, const Mesh& mesh, const TimingOptions& options) {
  CSHAPES_REQUIRE(options.repeats >= 1, "timing: repeats must be >= 1");
  TimingRow row;
  row.shape = shape;
  row.vertices = mesh.num_vertices();

  std::vector<double> pre;
  for (int r = 0; r < options.repeats; ++r) {
    auto start = WallClock::now();
    Edges E = mesh_edges(mesh.F);
    Eigen::VectorXd d = edge_lengths(mesh.V, E);
    pre.push_back(seconds_since(start));
    if (d.size() == 0) fail(shape, ": no edges");
  }
  row.coulomb_precompute = median(pre);
  const std::string stage = "Table 1, " + shape + ": ";
  row.coulomb_iteration = coulomb_iteration_seconds(mesh, options.repeats, 0, 0,
                                                    renamed_stage(options.progress, stage + "Coulomb iterations"));

  if (options.mds) {
    auto start = WallClock::now();
    GeodesicOptions geodesics = options.geodesics;
    geodesics.progress = renamed_stage(options.progress, stage + "all-pairs geodesics");
    DistanceMatrix D = all_pairs_geodesics(mesh, geodesics);
    const ProgressFn passes_progress = renamed_stage(options.progress, stage + "SMACOF passes");
    row.mds_precompute = seconds_since(start);
    // Start from the mesh itself (centred): the pass costs the same from any start.
    Points X = mesh.V.rowwise() - mesh.V.colwise().mean();
    std::vector<double> passes;
    for (int r = 0; r < options.repeats + 1; ++r) {
      auto t = WallClock::now();
      GuttmanTransform g = guttman_transform(D, X);
      double s = seconds_since(t);
      if (r > 0) passes.push_back(s);  // the first pass warms the caches
      X = g.X_next;
      if (passes_progress) passes_progress("passes", r + 1, options.repeats + 1);
    }
    row.mds_iteration = median(passes);
    row.mds_measured = true;
  }
  return row;
}

}  // namespace cshapes
