// cshapes canon MESH -o OUT --method coulomb [options]: the Coulomb canonical form (§2 of the paper).
// Output: the input's vertex order and faces; PLY carries a per-vertex `torn` flag (1: endpoint of a torn
// edge).
#include "cshapes/canon/coulomb.h"
#include "cli/command.h"
#include "cshapes/support/error.h"

namespace cshapes::cli {
namespace {

struct CoulombArgs {
  CoulombCanonOptions options;
  std::string scheme = to_string(CoulombCanonOptions{}.scheme);
  std::string start = to_string(CoulombCanonOptions{}.start);
  std::string step_rule = to_string(CoulombCanonOptions{}.step_rule);
  std::string step_gradient = to_string(CoulombCanonOptions{}.step_gradient);
  std::string norm = to_string(CoulombCanonOptions{}.projection.norm);
  std::string tear_guard = to_string(CoulombCanonOptions{}.tear_guard);
  std::string summation = to_string(CoulombCanonOptions{}.energy.summation);
} args;

void add_options(CLI::Option_group& g) {
  CoulombCanonOptions& o = args.options;
  g.add_option("--scheme", args.scheme,
               "paper: plain alternation of §2.1; momentum: Nesterov with restart (same "
               "fixed point, fewer iterations)")
      ->check(one_of({"paper", "momentum"}));
  g.add_option("--coulomb-start", args.start,
               "where the iteration starts: landmark-mds (an embedding of graph geodesics, the same for every "
               "pose) or input (the paper: the input's coordinates)")
      ->check(one_of({"landmark-mds", "input"}));
  g.add_option("--start-landmarks", o.start_landmarks, "landmarks of --coulomb-start landmark-mds")
      ->check(within(coulomb_limits::kStartLandmarks));
  g.add_option("--flatten", o.flatten,
               "per iteration, pull every point this fraction of the way towards the form's plane of largest "
               "spread (keeps left-right symmetric bodies symmetric); 0: off (the paper)")
      ->check(within(coulomb_limits::kFlatten));
  g.add_option("--step-rule", args.step_rule,
               "eq. (4) step c = factor·L/max‖∇E‖ with L = max-edge (paper), "
               "mean-edge, median-edge; or fixed")
      ->check(one_of({"max-edge", "mean-edge", "median-edge", "fixed"}));
  g.add_option("--step-gradient", args.step_gradient,
               "the step rule's denominator: max (paper: the fastest vertex moves factor·L) or mean "
               "(a typical vertex does)")
      ->check(one_of({"max", "mean"}));
  g.add_option("--step-factor", o.step_factor, "the factor of the step rule (paper: 0.1)")
      ->check(within(coulomb_limits::kStepFactor));
  g.add_option("--fixed-step", o.fixed_step,
               "c for --step-rule fixed; 0: the mean-edge c of the first iteration")
      ->check(within(coulomb_limits::kFixedStep));
  g.add_option("--coulomb-steps", o.coulomb_steps, "m: Coulomb steps per outer iteration")
      ->check(within(coulomb_limits::kCoulombSteps));
  g.add_option("--projection-steps", o.projection.steps, "k: projection sweeps per outer iteration")
      ->check(within(projection_limits::kSteps));
  g.add_option("--projection", args.norm, "l2: averaged projection (eq. 6); l1: weighted (eq. 8-9)")
      ->check(one_of({"l2", "l1"}));
  g.add_option("--l1-floor", o.projection.l1_floor, "L1 weights: |r-d| floored at this fraction of d")
      ->check(within(projection_limits::kL1Floor));
  g.add_option("--dilation", o.projection.dilation,
               "eq. (3): only pull lengths outside [d/c, c·d]; 1 = exact")
      ->check(within(projection_limits::kDilation));
  g.add_option("--tear-fraction", o.tear_fraction,
               "p: fraction of edges torn (by |r-d|) over all tears; 0: no tearing")
      ->check(within(coulomb_limits::kTearFraction));
  g.add_option("--tear-after", o.tear_after,
               "T: tear after this many iterations (or at convergence if earlier)")
      ->check(within(coulomb_limits::kTearAfter));
  g.add_option("--tear-times", o.tear_times, "how many times to tear")
      ->check(within(coulomb_limits::kTearTimes));
  g.add_option("--tear-interval", o.tear_interval, "iterations between repeated tears")
      ->check(within(coulomb_limits::kTearInterval));
  g.add_option("--tear-guard", args.tear_guard,
               "edges tearing must keep: connected (two per vertex, no part cut "
               "off), vertex (one per vertex: pairs and patches may be cut off and drift away)")
      ->check(one_of({"connected", "vertex"}));
  g.add_option("--coulomb-max-iterations", o.max_iterations, "maximum outer iterations")
      ->check(within(coulomb_limits::kMaxIterations));
  g.add_option("--coulomb-window", o.stop_window, "iterations between shape-change checks")
      ->check(within(coulomb_limits::kWindow));
  g.add_option("--coulomb-tolerance", o.stop_tolerance,
               "converged when the aligned RMS shape change over a window is below this × bbox diagonal")
      ->check(within(coulomb_limits::kTolerance));
  g.add_option("--momentum", o.momentum, "cap of Nesterov's momentum (scheme momentum)")
      ->check(within(coulomb_limits::kMomentum));
  g.add_option("--coulomb-summation", args.summation, "Coulomb sum: auto, direct, direct-float, fast")
      ->check(one_of({"auto", "direct", "direct-float", "fast"}));
  g.add_option(
       "--coulomb-accuracy", o.energy.accuracy,
       "fast summation in the iterations: target relative gradient error (the reported energy: 1e-3 or this, "
       "whichever is smaller)")
      ->check(within(coulomb_limits::kAccuracy));
  CoulombMultiresolutionOptions& mr = o.multiresolution;
  g.add_option("--coulomb-multiresolution-above", mr.above_vertices,
               "meshes with more vertices are canonized through a coarse remesh of their surface and refined "
               "(the single-level form inflates with n); 0: never")
      ->check(within(coulomb_limits::kMultiresolutionAbove));
  g.add_option("--coulomb-coarse-vertices", mr.coarse_vertices,
               "vertices of that coarse remesh (the resolution the defaults were chosen at)")
      ->check(within(coulomb_limits::kCoarseVertices));
  g.add_option("--coulomb-tear-rounds", mr.tear_rounds,
               "multiresolution: rounds that tear fine edges still overstretched after the refinement; 0: none")
      ->check(within(coulomb_limits::kTearRounds));
}

// The options as parsed (names checked here, so a typo fails before any work).
CoulombCanonOptions parsed_options() {
  CoulombCanonOptions options = args.options;
  options.scheme = parse_coulomb_scheme(args.scheme);
  options.start = parse_coulomb_start(args.start);
  options.step_rule = parse_coulomb_step_rule(args.step_rule);
  options.step_gradient = parse_step_gradient(args.step_gradient);
  options.projection.norm = parse_projection_norm(args.norm);
  options.tear_guard = parse_tear_guard(args.tear_guard);
  options.energy.summation = parse_coulomb_summation(args.summation);
  return options;
}

// Options that only one setting of another option reads: refused by name rather than ignored.
void validate() {
  const CoulombCanonOptions options = parsed_options();
  if (canon_option_given("--fixed-step") && options.step_rule != CoulombStepRule::Fixed)
    usage_fail("--fixed-step applies to --step-rule fixed only");
  if (canon_option_given("--l1-floor") && options.projection.norm != ProjectionNorm::L1)
    usage_fail("--l1-floor applies to --projection l1 only");
  if (canon_option_given("--momentum") && options.scheme != CoulombScheme::Momentum)
    usage_fail("--momentum applies to --scheme momentum only");
  if (canon_option_given("--start-landmarks") && options.start != CoulombStart::LandmarkMds)
    usage_fail("--start-landmarks applies to --coulomb-start landmark-mds only");
  if (options.multiresolution.above_vertices == 0)
    for (const char* fine : {"--coulomb-coarse-vertices", "--coulomb-tear-rounds"})
      if (canon_option_given(fine))
        usage_fail(fine, " applies only with multiresolution (--coulomb-multiresolution-above > 0)");
  if (options.tear_fraction == 0)
    for (const char* tearing : {"--tear-after", "--tear-times", "--tear-interval", "--tear-guard"})
      if (canon_option_given(tearing))
        usage_fail(tearing, " applies only when tearing (--tear-fraction > 0)");
}

void configure(CanonicalFormOptions& o, bool /*single_mesh*/) {
  validate();
  o.coulomb = parsed_options();
}

const bool registered =
    register_canon_method({"coulomb",
                           "Coulomb shape: electrostatic repulsion under edge-length constraints (§2)",
                           add_options,
                           configure,
                           {},
                           validate});

}  // namespace
}  // namespace cshapes::cli
