// Method coulomb (pipeline/canonical_form_methods.h): the Coulomb canonical form, §2 of the paper
// (canon/coulomb.h), on the mesh's edges or a point cloud's kNN graph.
#include <nlohmann/json.hpp>
#include <tuple>

#include "cshapes/canon/coulomb.h"
#include "cshapes/canon/coulomb_multiresolution.h"
#include "cshapes/canon/coulomb_start.h"
#include "cshapes/pipeline/canonical_form_methods.h"
#include "cshapes/support/error.h"
#include "cshapes/support/format.h"
#include "cshapes/support/timing.h"

namespace cshapes {

namespace {

CanonicalForm coulomb_compute(const Mesh& mesh, const CanonicalFormOptions& options, const GivenDistances&) {
  auto start = WallClock::now();
  const Edges E = constraint_edges(mesh, options.knn);
  if (mesh.is_point_cloud()) {
    // A point cloud's kNN graph stands in for the mesh's edges; its parts would drift apart if it fell apart.
    const Components components = connected_components(mesh.num_vertices(), E);
    CSHAPES_REQUIRE(components.count == 1, options.name, ": the ", options.knn.k,
                    "-nearest-neighbour graph has ", components.count,
                    " components; its parts would drift apart: raise --knn");
    say(options.note, options.name + ": point cloud, " + std::to_string(E.rows()) +
                          " kNN edges (k = " + std::to_string(options.knn.k) + ")");
  }
  CanonicalForm form;
  form.precompute_seconds = seconds_since(start);
  CoulombCanonOptions co = options.coulomb;
  if (!co.progress) co.progress = options.progress;
  // A mesh whose resolution is above options.coulomb.multiresolution.above_resolution goes through a coarse
  // version of its surface (canon/coulomb_multiresolution.h); point clouds and coarser meshes run the
  // iteration directly.
  CoulombCanonResult r;
  std::string multiresolution;
  if (mesh.is_point_cloud()) {
    r = coulomb_canonical_form(mesh.V, E, co);
  } else {
    CoulombMultiresolutionResult mr = coulomb_multiresolution(mesh, co);
    if (mr.used) say(options.note, "coulomb: " + mr.note);
    multiresolution = mr.note;
    r = std::move(mr.result);
  }
  form.X = r.X;
  form.torn = r.torn_vertices;
  form.iterations = r.iterations;
  form.solve_seconds = r.seconds;
  form.seconds_per_iteration = r.iterations ? r.seconds / r.iterations : 0;
  form.history_columns = {"iteration",  "energy",   "mean_violation", "max_violation", "step",
                          "max_move",   "limited_moves", "torn_edges", "shape_change",  "momentum",
                          "relaxation", "seconds"};
  for (const CoulombIterationRecord& h : r.history)
    form.history_rows.push_back({double(h.iteration), h.energy, h.mean_violation, h.max_violation, h.step,
                                 h.max_move, double(h.limited_moves), double(h.torn_edges), h.shape_change,
                                 h.momentum, h.relaxation, h.seconds});
  form.torn_edges = r.torn_edges;  // left out of the form's quality check
  form.breakdown = r.not_converged;  // a form that did not converge fails the check, saying so
  form.details = nlohmann::json{{"vertices", mesh.num_vertices()},
                                {"edges", E.rows()},
                                {"torn_edges", r.torn_edges.rows()},
                                {"iterations", r.iterations},
                                {"multiresolution", multiresolution},
                                {"converged", r.converged},
                                {"stop_reason", r.stop_reason},
                                {"energy", r.energy},
                                {"mean_violation", r.violation.mean_relative},
                                {"max_violation", r.violation.max_relative},
                                {"median_length_ratio", r.violation.median_length_ratio},
                                {"seconds", r.seconds},
                                {"scheme", to_string(co.scheme)},
                                {"start", r.start},
                                {"flatten", co.flatten},
                                {"flatten_plane", to_string(co.flatten_plane)},
                                {"flatten_decision", r.flatten_plane},
                                {"bridge_detour", co.bridge_detour},
                                {"move_limit", co.move_limit},
                                {"step_rule", to_string(co.step_rule)},
                                {"step_gradient", to_string(co.step_gradient)},
                                {"projection", to_string(co.projection.norm)},
                                {"projection_steps", co.projection.steps}};
  say(options.note, "coulomb: started at " + r.start);
  if (!r.flatten_plane.empty()) say(options.note, "coulomb: flatten: " + r.flatten_plane);
  say(options.note, "coulomb: " + std::to_string(r.iterations) + " iterations (" + r.stop_reason + ") in " +
                        significant(r.seconds) + " s; edge lengths off their rest lengths by " +
                        significant(100 * r.violation.mean_relative) + "% on average, " +
                        std::to_string(r.torn_edges.rows()) + " edges torn");
  return form;
}

// The paper's algorithm as §2 writes it (docs/coulomb-defaults.md, "The paper's preset"): start at the input,
// plain alternation of one Coulomb step (eq. 4) with the step heuristic c = 0.1 · max d_ij / max ‖∇_i E‖ and
// the averaged projection (eq. 6); one tear of 1% of the edges by |r − d| after the initial repulsion (100
// iterations, the end of the paper's "typically 10–100"), with no guard beyond the weakest this code has; no
// flatten, no second run around glued tubes, no coarse level. What the paper leaves open keeps the default:
// k = 10 projection sweeps (its Fig. 5 shows 1, 10, 100), the stopping rule, the summation.
CoulombCanonOptions paper_coulomb_options() {
  CoulombCanonOptions c;
  c.scheme = CoulombScheme::Paper;
  c.start = CoulombStart::Input;
  c.flatten = 0;
  c.bridge_detour = 0;
  c.step_rule = CoulombStepRule::MaxEdge;
  c.step_gradient = StepGradient::Max;
  c.step_factor = 0.1;
  c.coulomb_steps = 1;
  c.projection.norm = ProjectionNorm::L2;
  c.tear_fraction = 0.01;
  c.tear_after = 100;
  c.tear_times = 1;
  c.tear_guard = TearGuard::Vertex;
  c.multiresolution.above_resolution = 0;
  c.move_limit = 0;
  return c;
}

// --coulomb-preset: sets every option it covers, first (the options given beside it then change single ones).
// Its value as read back: "paper" while every field it sets holds the paper's value, else "default".
MethodOption coulomb_preset_option() {
  MethodOption o = option_of(
      "coulomb_preset", MethodOption::Type::Choice,
      "default: this library's choices (docs/coulomb-defaults.md); paper: the paper's algorithm as §2 writes "
      "it (start at the input, plain alternation, its step rule, one tear after 100 iterations); the single "
      "settings, given beside it, change it: see --help-all",
      {"coulomb"});
  o.choices = {"default", "paper"};
  auto covered = [](const CoulombCanonOptions& c) {
    return std::make_tuple(c.scheme, c.start, c.flatten, c.bridge_detour, c.step_rule, c.step_gradient,
                           c.step_factor, c.coulomb_steps, c.projection.norm, c.tear_fraction, c.tear_after,
                           c.tear_times, c.tear_guard, c.multiresolution.above_resolution, c.move_limit);
  };
  o.get = [covered](const CanonicalFormOptions& c) {
    return OptionValue(std::string(covered(c.coulomb) == covered(paper_coulomb_options()) ? "paper" : "default"));
  };
  o.set = [](CanonicalFormOptions& c, const OptionValue& v) {
    const CoulombCanonOptions preset =
        std::get<std::string>(v) == "paper" ? paper_coulomb_options() : CoulombCanonOptions{};
    CoulombCanonOptions& t = c.coulomb;
    t.scheme = preset.scheme;
    t.start = preset.start;
    t.flatten = preset.flatten;
    t.bridge_detour = preset.bridge_detour;
    t.step_rule = preset.step_rule;
    t.step_gradient = preset.step_gradient;
    t.step_factor = preset.step_factor;
    t.coulomb_steps = preset.coulomb_steps;
    t.projection.norm = preset.projection.norm;
    t.tear_fraction = preset.tear_fraction;
    t.tear_after = preset.tear_after;
    t.tear_times = preset.tear_times;
    t.tear_guard = preset.tear_guard;
    t.multiresolution.above_resolution = preset.multiresolution.above_resolution;
    t.move_limit = preset.move_limit;
  };
  return o;
}

// The options of method coulomb, each once (pipeline/method_options.h): `cshapes canon`'s "coulomb options",
// coulomb()'s and canonical_form()'s keywords. The preset first (it sets the others), then the start, the
// step and the projection:
using Ref = CanonicalFormOptions&;
std::vector<MethodOption> coulomb_step_options() {
  using C = MethodOption::Condition;
  const std::vector<std::string> f = {"coulomb"};
  std::vector<MethodOption> o;
  o.push_back(coulomb_preset_option());
  o.push_back(choice_option<CoulombScheme>(
      "scheme",
      "paper: plain alternation of §2.1; momentum: Nesterov with restart (same fixed point, fewer "
      "iterations)",
      {"paper", "momentum"}, f, [](Ref c) -> CoulombScheme& { return c.coulomb.scheme; }, to_string,
      parse_coulomb_scheme));
  o.push_back(choice_option<CoulombStart>(
      "coulomb_start",
      "where the iteration starts: landmark-mds (an embedding of graph geodesics, the same for every pose) "
      "or "
      "input (the paper: the input's coordinates)",
      {"landmark-mds", "input"}, f, [](Ref c) -> CoulombStart& { return c.coulomb.start; }, to_string,
      parse_coulomb_start));
  o.push_back(integer_option<Index>("coulomb_start_landmarks", "landmarks of --coulomb-start landmark-mds",
                                    coulomb_limits::kStartLandmarks, f,
                                    [](Ref c) -> Index& { return c.coulomb.start_landmarks; }));
  o.back().applies_when = C{"coulomb_start", {"landmark-mds"}, ""};
  o.push_back(
      number_option("flatten",
                    "per iteration, pull every point this fraction of the way towards the form's plane of "
                    "largest spread (keeps left-right symmetric bodies symmetric); 0: off (the paper)",
                    coulomb_limits::kFlatten, f, [](Ref c) -> double& { return c.coulomb.flatten; }));
  o.push_back(choice_option<FlattenPlane>(
      "flatten_plane",
      "the plane --flatten pulls towards: spread (the plane of largest spread) or keep-mirror (the same, "
      "unless "
      "that plane is the start's mirror, as a four-legged shape's is: then no pull)",
      {"keep-mirror", "spread"}, f, [](Ref c) -> FlattenPlane& { return c.coulomb.flatten_plane; }, to_string,
      parse_flatten_plane));
  o.push_back(number_option(
      "bridge_detour",
      "after the iteration, torn edges whose ends lie farther apart along the other "
      "edges than this many bbox diagonals and than their crack is long are bridges "
      "(glued tubes); if there are any, iterate again without them from the start; 0: off "
      "(the paper)",
      coulomb_limits::kBridgeDetour, f, [](Ref c) -> double& { return c.coulomb.bridge_detour; }));
  o.back().applies_when = C{"coulomb_start", {"landmark-mds"}, ""};
  o.push_back(choice_option<CoulombStepRule>(
      "step_rule",
      "eq. (4) step c = factor·L/max‖∇E‖ with L = max-edge (paper), mean-edge, median-edge; or fixed",
      {"max-edge", "mean-edge", "median-edge", "fixed"}, f,
      [](Ref c) -> CoulombStepRule& { return c.coulomb.step_rule; }, to_string, parse_coulomb_step_rule));
  o.push_back(choice_option<StepGradient>(
      "step_gradient",
      "the step rule's denominator: max (paper: the fastest vertex moves factor·L) or mean (a typical vertex "
      "does)",
      {"max", "mean"}, f, [](Ref c) -> StepGradient& { return c.coulomb.step_gradient; }, to_string,
      parse_step_gradient));
  o.push_back(number_option("step_factor", "the factor of the step rule (paper: 0.1)",
                            coulomb_limits::kStepFactor, f,
                            [](Ref c) -> double& { return c.coulomb.step_factor; }));
  o.push_back(
      number_option("fixed_step", "c for --step-rule fixed; 0: the mean-edge c of the first iteration",
                    coulomb_limits::kFixedStep, f, [](Ref c) -> double& { return c.coulomb.fixed_step; }));
  o.back().applies_when = C{"step_rule", {"fixed"}, ""};
  o.push_back(integer_option<int>("coulomb_steps", "m: Coulomb steps per outer iteration",
                                  coulomb_limits::kCoulombSteps, f,
                                  [](Ref c) -> int& { return c.coulomb.coulomb_steps; }));
  o.push_back(number_option("move_limit",
                            "no vertex moves farther in one Coulomb step than this times its shortest edge "
                            "(the ends of short edges otherwise rattle and the form depends on rounding); 0: "
                            "no limit (the paper)",
                            coulomb_limits::kMoveLimit, f, [](Ref c) -> double& { return c.coulomb.move_limit; }));
  o.push_back(integer_option<int>("projection_steps", "k: projection sweeps per outer iteration",
                                  projection_limits::kSteps, f,
                                  [](Ref c) -> int& { return c.coulomb.projection.steps; }));
  o.push_back(choice_option<ProjectionNorm>(
      "projection", "l2: averaged projection (eq. 6); l1: weighted (eq. 8-9)", {"l2", "l1"}, f,
      [](Ref c) -> ProjectionNorm& { return c.coulomb.projection.norm; }, to_string, parse_projection_norm));
  o.push_back(number_option("l1_floor", "L1 weights: |r-d| floored at this fraction of d",
                            projection_limits::kL1Floor, f,
                            [](Ref c) -> double& { return c.coulomb.projection.l1_floor; }));
  o.back().applies_when = C{"projection", {"l1"}, ""};
  o.push_back(number_option("dilation", "eq. (3): only pull lengths outside [d/c, c·d]; 1 = exact",
                            projection_limits::kDilation, f,
                            [](Ref c) -> double& { return c.coulomb.projection.dilation; }));
  return o;
}

// Tearing, stopping, the Coulomb sum and the multiresolution path.
std::vector<MethodOption> coulomb_tearing_and_stop_options() {
  using C = MethodOption::Condition;
  const std::vector<std::string> f = {"coulomb"};
  std::vector<MethodOption> o;
  o.push_back(number_option(
      "tear_fraction", "p: fraction of edges torn (by |r-d|) over all tears; 0: no tearing",
      coulomb_limits::kTearFraction, f, [](Ref c) -> double& { return c.coulomb.tear_fraction; }));
  const C tearing{"tear_fraction", {}, "when tearing"};
  o.push_back(
      integer_option<int>("tear_after", "T: tear after this many iterations (or at convergence if earlier)",
                          coulomb_limits::kTearAfter, f, [](Ref c) -> int& { return c.coulomb.tear_after; }));
  o.back().applies_when = tearing;
  o.push_back(integer_option<int>("tear_times", "how many times to tear", coulomb_limits::kTearTimes, f,
                                  [](Ref c) -> int& { return c.coulomb.tear_times; }));
  o.back().applies_when = tearing;
  o.push_back(integer_option<int>("tear_interval", "iterations between repeated tears",
                                  coulomb_limits::kTearInterval, f,
                                  [](Ref c) -> int& { return c.coulomb.tear_interval; }));
  o.back().applies_when = tearing;
  o.push_back(choice_option<TearGuard>(
      "tear_guard",
      "edges tearing must keep: connected (two per vertex, no part cut off), vertex (one per vertex: pairs "
      "and "
      "patches may be cut off and drift away)",
      {"connected", "vertex"}, f, [](Ref c) -> TearGuard& { return c.coulomb.tear_guard; }, to_string,
      parse_tear_guard));
  o.back().applies_when = tearing;
  o.push_back(integer_option<int>("coulomb_max_iterations", "maximum outer iterations",
                                  coulomb_limits::kMaxIterations, f,
                                  [](Ref c) -> int& { return c.coulomb.max_iterations; }));
  o.push_back(integer_option<int>("coulomb_window", "iterations between shape-change checks",
                                  coulomb_limits::kWindow, f,
                                  [](Ref c) -> int& { return c.coulomb.stop_window; }));
  o.push_back(number_option(
      "coulomb_tolerance",
      "converged when the aligned RMS shape change over a window is below this × bbox diagonal",
      coulomb_limits::kTolerance, f, [](Ref c) -> double& { return c.coulomb.stop_tolerance; }));
  o.push_back(number_option("momentum", "cap of Nesterov's momentum (scheme momentum)",
                            coulomb_limits::kMomentum, f,
                            [](Ref c) -> double& { return c.coulomb.momentum; }));
  o.back().applies_when = C{"scheme", {"momentum"}, ""};
  o.push_back(integer_option<int>(
      "coulomb_stall_windows",
      "after this many stopping windows in a row without a new smallest shape change (since the last tear), "
      "the momentum is dropped, and after each further such run the iteration is relaxed (X + w (T(X) - X), w "
      "halving to 1/8: the same fixed points); 0: never",
      coulomb_limits::kStallWindows, f, [](Ref c) -> int& { return c.coulomb.stall_windows; }));
  o.back().applies_when = C{"scheme", {"momentum"}, ""};
  o.push_back(choice_option<CoulombOptions::Summation>(
      "coulomb_summation", "Coulomb sum: auto, direct, direct-float, fast",
      {"auto", "direct", "direct-float", "fast"}, f,
      [](Ref c) -> CoulombOptions::Summation& { return c.coulomb.energy.summation; }, to_string,
      parse_coulomb_summation));
  o.push_back(number_option("coulomb_accuracy",
                            "fast summation in the iterations: target relative gradient error (the reported "
                            "energy: 1e-3 or this, whichever is smaller)",
                            coulomb_limits::kAccuracy, f,
                            [](Ref c) -> double& { return c.coulomb.energy.accuracy; }));
  o.push_back(integer_option<int>(
      "coulomb_fmm_rebuild_every",
      "fast summation in the iterations: its octree and lists are kept between iterations (refit to the "
      "moved vertices, pairs that fail the opening criterion split) and built afresh every this many; 1: "
      "every iteration",
      coulomb_limits::kFmmRebuildEvery, f, [](Ref c) -> int& { return c.coulomb.fmm_rebuild_every; }));
  o.push_back(integer_option<Index>(
      "coulomb_multiresolution_above",
      "meshes whose resolution (area / (sqrt(3)/2 mean edge^2): about the vertex count of an even "
      "triangulation) is above this are canonized through a coarse remesh of their surface and refined (the "
      "single-level form inflates with the shape's size over the mean edge); 0: never",
      coulomb_limits::kMultiresolutionAbove, f,
      [](Ref c) -> Index& { return c.coulomb.multiresolution.above_resolution; }));
  const C multiresolution{"coulomb_multiresolution_above", {}, "with multiresolution"};
  o.push_back(
      integer_option<Index>("coulomb_coarse_vertices",
                            "vertices of that coarse remesh (the resolution the defaults were chosen at)",
                            coulomb_limits::kCoarseVertices, f,
                            [](Ref c) -> Index& { return c.coulomb.multiresolution.coarse_vertices; }));
  o.back().applies_when = multiresolution;
  o.push_back(integer_option<int>(
      "coulomb_tear_rounds",
      "multiresolution: rounds that tear fine edges still overstretched after the refinement (after the "
      "first 20, each with an eighth of the projections); 0: none",
      coulomb_limits::kTearRounds, f, [](Ref c) -> int& { return c.coulomb.multiresolution.tear_rounds; }));
  o.back().applies_when = multiresolution;
  return o;
}

}  // namespace

CanonicalFormMethod coulomb_method() {
  CanonicalFormMethod m;
  m.name = "coulomb";
  m.title = "Coulomb";
  m.summary = "Coulomb shape: electrostatic repulsion under edge-length constraints (§2)";
  m.requirements = MeshRequirements::edge_graph();
  m.repair_purpose = "Coulomb canonization (the largest component's edge graph)";
  m.uses_geodesic_matrix = false;
  m.options = coulomb_step_options();
  for (MethodOption& option : coulomb_tearing_and_stop_options()) m.options.push_back(std::move(option));
  for (MethodOption& option : m.options) option.advanced = option.name != "coulomb_preset";
  m.reads = {"coulomb"};
  m.has_history = true;
  m.marks_torn = true;
  // 2: the kernels without fused multiply-adds, the same bytes under every target; 3: the form a function of
  // the shape (the start's landmarks and rows, the float sum's order, ties in tearing); 4: the start in its own
  // frame, the form turned onto the input at the end
  m.results_version = 4;
  m.compute = coulomb_compute;
  return m;
}

}  // namespace cshapes
