// `cshapes canon --method cmds|smacof`: MDS canonical forms (Elad & Kimmel) of a mesh, from its all-pairs
// geodesic distances (computed here, or read with --distances).
#include <algorithm>
#include <cmath>

#include "canon/classical_mds.h"
#include "canon/smacof.h"
#include "core/error.h"
#include "core/geodesics.h"
#include "core/knn_graph.h"
#include "pipeline/form_quality_json.h"
#include "experiments/command.h"

namespace cshapes::cli {
namespace {

struct MdsArgs {
  std::string geodesics;  // empty: the command's default (canon: fmm, the paper's; distmat, experiment: heat)
  std::string distances;
  int iterations = 300;
  double tolerance = 1e-5;
  std::string init = "cmds";
  std::string accelerate = "none";
  int window = 6;
  std::string weights = "uniform";
} args;

// The job's distance matrix: read (and restricted to the job's vertices when the mesh was reduced to its
// largest component) or computed.
DistanceMatrix job_distances(const CanonJob& job) {
  const Index n = job.mesh.num_vertices();
  if (args.distances.empty()) {
    GeodesicOptions go;
    go.method = parse_geodesic_method(args.geodesics.empty() ? "fmm" : args.geodesics);
    go.progress = progress_printer();
    return all_pairs_geodesics(job.mesh, go);
  }
  DistanceMatrix D = read_distance_matrix(args.distances);
  if (D.rows() == n) return D;
  const Index needed =
      job.vertex_map.empty() ? n : *std::max_element(job.vertex_map.begin(), job.vertex_map.end()) + 1;
  if (job.vertex_map.empty() || D.rows() < needed)
    fail(args.distances, ": has ", D.rows(), " points but ", job.input_path, " has ", n,
         " vertices (in the part kept)");
  // The input was repaired (vertices dropped or split): the rows and columns of the vertices it maps to.
  require_memory(distance_matrix_bytes(n), "restricting " + args.distances + " to the kept component");
  DistanceMatrix sub(n, n);
  for (Index j = 0; j < n; ++j)
    for (Index i = 0; i < n; ++i) sub(i, j) = D(job.vertex_map[i], job.vertex_map[j]);
  return sub;
}

nlohmann::json cmds_summary(const ClassicalMdsResult& r) {
  return {{"eigenvalues", {r.eigenvalues[0], r.eigenvalues[1], r.eigenvalues[2]}},
          {"most_negative_eigenvalue", std::isfinite(r.most_negative_eigenvalue)
                                           ? nlohmann::json(r.most_negative_eigenvalue)
                                           : nlohmann::json(nullptr)},
          {"trace", r.trace},
          {"frobenius_squared", r.frobenius_squared},
          {"explained_energy", r.explained_energy},
          {"negative_mass_lower_bound", r.negative_mass_lower_bound},
          {"negative_energy_upper_bound", r.negative_energy_upper_bound},
          {"matrix_products", r.matrix_products},
          {"seconds", r.seconds}};
}

// The form's edge stretch and runaway vertices (canon/form_quality.h), over the mesh's edges (a point cloud's
// kNN graph).
nlohmann::json quality_summary(const CanonJob& job, const Points& X) {
  const Edges E =
      job.mesh.is_point_cloud() ? knn_graph(job.mesh.V, KnnGraphOptions{}) : mesh_edges(job.mesh.F);
  const FormQuality q = form_quality(job.mesh.V, E, X);
  note("form quality " + q.description);
  return form_quality_json(q);
}

ClassicalMdsResult run_cmds(const DistanceMatrix& D) {
  ClassicalMdsResult r = classical_mds(D);
  note("classical MDS: eigenvalues " + std::to_string(r.eigenvalues[0]) + ", " +
       std::to_string(r.eigenvalues[1]) + ", " + std::to_string(r.eigenvalues[2]) + "; 3-D keeps " +
       std::to_string(100 * r.explained_energy) + "% of the spectrum's energy; most negative eigenvalue " +
       std::to_string(r.most_negative_eigenvalue) + " in " + std::to_string(r.seconds) + " s");
  return r;
}

CanonOutput canon_cmds(const CanonJob& job) {
  DistanceMatrix D = job_distances(job);
  ClassicalMdsResult r = run_cmds(D);
  CanonOutput out;
  out.X = r.X;
  out.summary = {{"classical_mds", cmds_summary(r)}, {"form_quality", quality_summary(job, r.X)}};
  return out;
}

CanonOutput canon_smacof(const CanonJob& job) {
  SmacofOptions options;
  options.max_iterations = args.iterations;
  options.tolerance = args.tolerance;
  options.acceleration = parse_smacof_acceleration(args.accelerate);
  options.extrapolation_window = args.window;
  options.progress = progress_printer();
  if (args.weights == "area") options.vertex_weights = vertex_area_weights(job.mesh);

  DistanceMatrix D = job_distances(job);
  CanonOutput out;
  Points X0;
  if (args.init == "cmds") {
    ClassicalMdsResult r = run_cmds(D);
    X0 = r.X;
    out.summary["classical_mds"] = cmds_summary(r);
  } else {
    X0 = job.mesh.V;
  }
  SmacofResult r = smacof(D, X0, options);
  note("SMACOF: normalised stress " + std::to_string(r.stress_history.front()) + " -> " +
       std::to_string(r.normalized_stress) + " in " + std::to_string(r.iterations) + " iterations (" +
       r.stop_reason + "), " + std::to_string(r.seconds_per_iteration) + " s per iteration");
  out.X = r.X;
  out.history_columns = {"iteration", "passes", "normalized_stress", "extrapolated"};
  for (size_t k = 0; k < r.stress_history.size(); ++k)
    out.history_rows.push_back({static_cast<double>(k), static_cast<double>(r.passes_history[k]),
                                r.stress_history[k], r.extrapolated_history[k] ? 1.0 : 0.0});
  out.summary["smacof"] = {{"normalized_stress", r.normalized_stress},
                           {"initial_normalized_stress", r.stress_history.front()},
                           {"iterations", r.iterations},
                           {"stop_reason", r.stop_reason},
                           {"acceleration", to_string(options.acceleration)},
                           {"extrapolations_accepted", r.extrapolations_accepted},
                           {"extrapolations_rejected", r.extrapolations_rejected},
                           {"init", args.init},
                           {"weights", args.weights},
                           {"seconds", r.seconds},
                           {"seconds_per_iteration", r.seconds_per_iteration}};
  out.summary["form_quality"] = quality_summary(job, r.X);
  return out;
}

// distmat and experiment paper: the same options through canonical_form(), which computes the geodesics
// itself and starts SMACOF from classical MDS with uniform weights.
void validate_mds() {
  if (canon_option_given("--geodesics") && canon_option_given("--distances"))
    usage_fail("--geodesics and --distances exclude each other (--distances reads the distances instead)");
}

void configure_mds(CanonicalFormOptions& o) {
  validate_mds();
  if (!args.geodesics.empty()) o.geodesics.method = parse_geodesic_method(args.geodesics);
  if (!args.distances.empty())
    usage_fail(
        "--distances: only `cshapes canon` reads a precomputed distance matrix (here every shape needs "
        "its own)");
}

void validate_smacof() {
  validate_mds();  // cmds' group (--geodesics, --distances) serves smacof too
  if (canon_option_given("--window") && args.accelerate == "none")
    usage_fail("--window applies to --accelerate rre or mpe only");
}

void configure_smacof(CanonicalFormOptions& o) {
  validate_smacof();
  o.smacof.max_iterations = args.iterations;
  o.smacof.tolerance = args.tolerance;
  o.smacof.acceleration = parse_smacof_acceleration(args.accelerate);
  o.smacof.extrapolation_window = args.window;
  if (args.init != "cmds")
    usage_fail("--init ", args.init,
               ": only `cshapes canon` starts SMACOF from the mesh; here it starts from classical MDS");
  if (args.weights != "uniform")
    usage_fail("--weights ", args.weights,
               ": only `cshapes canon` weights SMACOF by vertex areas; here weights are uniform");
}

// Options shared by both methods live in the cmds group (CLI11 needs each name once).
const bool cmds_registered = register_canon_method(
    {"cmds",
     "classical MDS (Young-Householder) of all-pairs geodesic distances",
     [](CLI::Option_group& g) {
       g.add_option(
            "--geodesics", args.geodesics,
            "cmds/smacof: geodesic distances to embed (heat, heat-cgal, fmm, exact, graph); default: fmm "
            "(the paper's) in canon, heat in distmat and experiment paper")
           ->check(one_of({"heat", "heat-cgal", "fmm", "exact", "graph"}));
       g.add_option("--distances", args.distances,
                    "cmds/smacof: read the n×n distance matrix (.bin, see `cshapes geodesics`) instead");
     },
     canon_cmds,
     configure_mds,
     {"smacof"},
     validate_mds});

const bool smacof_registered = register_canon_method(
    {"smacof",
     "SMACOF metric MDS (Guttman transforms) of all-pairs geodesic distances",
     [](CLI::Option_group& g) {
       g.add_option("--iters", args.iterations, "smacof: maximum iterations (passes over D)")
           ->capture_default_str()
           ->check(integer_in(0, 100000000));
       g.add_option("--tolerance", args.tolerance,
                    "smacof: stop when the relative stress decrease is below this")
           ->capture_default_str()
           ->check(number_at_least(0));
       g.add_option("--init", args.init, "smacof: initial configuration: cmds (classical MDS) or mesh")
           ->capture_default_str()
           ->check(one_of({"cmds", "mesh"}));
       g.add_option("--accelerate", args.accelerate, "smacof: vector extrapolation: none, rre or mpe")
           ->capture_default_str()
           ->check(one_of({"none", "rre", "mpe"}));
       g.add_option("--window", args.window, "smacof: Guttman steps per extrapolation")
           ->capture_default_str()
           ->check(integer_in(2, 1000));
       g.add_option("--weights", args.weights,
                    "smacof: pair weights w_i*w_j from uniform or area (vertex areas)")
           ->capture_default_str()
           ->check(one_of({"uniform", "area"}));
     },
     canon_smacof,
     configure_smacof,
     {},
     validate_smacof});

}  // namespace
}  // namespace cshapes::cli
