// The options of `--method cmds|smacof`: MDS canonical forms (Elad & Kimmel) of a mesh, from its all-pairs
// geodesic distances (computed, or read with --distances by `cshapes canon`); pipeline/canonical_forms.h
// computes them.
#include "cshapes/canon/landmark_mds.h"
#include "cshapes/canon/smacof.h"
#include "cli/command.h"
#include "cshapes/support/error.h"
#include "cshapes/geodesics/geodesics.h"

namespace cshapes::cli {
namespace {

struct MdsArgs {
  std::string geodesics;  // empty: the library's default (heat, in every command)
  std::string distances;
  int iterations = 300;
  double tolerance = 1e-5;
  std::string init = "cmds";
  std::string accelerate = "none";
  int window = 6;
  std::string weights = "uniform";
  std::string mds_solver = to_string(MdsSolverOptions{}.solver);
  long landmarks = MdsSolverOptions{}.landmarks;
  double fold_overstretch = MdsSolverOptions{}.fold_overstretch;
} args;

void validate_mds() {
  if (canon_option_given("--geodesics") && canon_option_given("--distances"))
    usage_fail("--geodesics and --distances exclude each other (--distances reads the distances instead)");
}

void configure_mds(CanonicalFormOptions& o, bool single_mesh) {
  validate_mds();
  if (!args.geodesics.empty()) o.geodesics.method = parse_geodesic_method(args.geodesics);
  if (!args.distances.empty() && !single_mesh)
    usage_fail(
        "--distances: only `cshapes canon` reads a precomputed distance matrix (here every shape needs "
        "its own)");
  o.distances_file = args.distances;
  o.mds_solver.solver = parse_mds_solver(args.mds_solver);
  o.mds_solver.landmarks = args.landmarks;
  if (canon_option_given("--landmarks") && o.mds_solver.solver == MdsSolver::Full)
    usage_fail("--landmarks applies to --mds-solver landmarks or auto only");
}

void validate_smacof() {
  validate_mds();  // cmds' group (--geodesics, --distances) serves smacof too
  if (canon_option_given("--window") && args.accelerate == "none")
    usage_fail("--window applies to --accelerate rre or mpe only");
}

void configure_smacof(CanonicalFormOptions& o, bool single_mesh) {
  validate_smacof();
  o.smacof.max_iterations = args.iterations;
  o.smacof.tolerance = args.tolerance;
  o.smacof.acceleration = parse_smacof_acceleration(args.accelerate);
  o.smacof.extrapolation_window = args.window;
  o.smacof_init = parse_smacof_init(args.init);
  o.smacof_weights = parse_smacof_weights(args.weights);
  o.mds_solver.fold_overstretch = args.fold_overstretch;
  if (args.fold_overstretch > 0 && args.fold_overstretch <= 1)
    usage_fail("--fold-overstretch: expected 0 (no repair) or a number above 1, got ", args.fold_overstretch);
  if (canon_option_given("--fold-overstretch") && o.mds_solver.solver == MdsSolver::Full)
    usage_fail("--fold-overstretch applies to --mds-solver landmarks or auto only");
  if (o.smacof_init != SmacofInit::ClassicalMds && !single_mesh)
    usage_fail("--init ", args.init,
               ": only `cshapes canon` starts SMACOF from the mesh; here it starts from classical MDS");
  if (o.smacof_weights != SmacofWeights::Uniform && !single_mesh)
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
            "cmds/smacof: geodesic distances to embed (heat, heat-cgal, fmm, exact, graph); default: heat "
            "in every command and in Python (fmm is the paper's)")
           ->check(one_of({"heat", "heat-cgal", "fmm", "exact", "graph"}));
       g.add_option("--distances", args.distances,
                    "cmds/smacof: read the n×n distance matrix (.bin, see `cshapes geodesics`) instead");
       g.add_option("--mds-solver", args.mds_solver,
                    "cmds/smacof: full (the n×n geodesic matrix), landmarks (L rows: landmark MDS, SMACOF on "
                    "the landmarks), or auto (landmarks above 12,000 vertices or when the matrix would take "
                    "more than half the free memory)")
           ->capture_default_str()
           ->check(one_of(mds_solver_names()));
       g.add_option("--landmarks", args.landmarks,
                    "cmds/smacof: landmarks L for --mds-solver landmarks|auto (farthest-point sampling)")
           ->capture_default_str()
           ->check(CLI::Range(4L, 1000000L));
     },
     configure_mds,
     {"smacof", "spectral-mds"},  // --geodesics: spectral-mds's geodesic rows too
     validate_mds});

const bool smacof_registered = register_canon_method(
    {"smacof",
     "SMACOF metric MDS (Guttman transforms) of all-pairs geodesic distances",
     [](CLI::Option_group& g) {
       g.add_option("--iters", args.iterations, "smacof: maximum iterations (passes over D)")
           ->capture_default_str()
           ->check(within(smacof_limits::kIterations));
       g.add_option("--tolerance", args.tolerance,
                    "smacof: stop when the relative stress decrease is below this")
           ->capture_default_str()
           ->check(within(smacof_limits::kTolerance));
       g.add_option("--init", args.init, "smacof: initial configuration: cmds (classical MDS) or mesh")
           ->capture_default_str()
           ->check(one_of(smacof_init_names()));
       g.add_option("--accelerate", args.accelerate, "smacof: vector extrapolation: none, rre or mpe")
           ->capture_default_str()
           ->check(one_of({"none", "rre", "mpe"}));
       g.add_option("--window", args.window, "smacof: Guttman steps per extrapolation")
           ->capture_default_str()
           ->check(within(smacof_limits::kWindow));
       g.add_option("--weights", args.weights,
                    "smacof: pair weights w_i*w_j from uniform or area (vertex areas)")
           ->capture_default_str()
           ->check(one_of(smacof_weights_names()));
       g.add_option("--fold-overstretch", args.fold_overstretch,
                    "smacof on landmarks: points on edges longer than this × their input length (or the mean "
                    "edge) are placed again beside their neighbours; 0: no repair")
           ->capture_default_str()
           ->check(within(landmark_limits::kFoldOverstretch));
     },
     configure_smacof,
     {},
     validate_smacof});

}  // namespace
}  // namespace cshapes::cli
