#include "cshapes/canon/coulomb.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <memory>
#include <numeric>

#include <Eigen/Eigenvalues>

#include "cshapes/canon/coulomb_bridges.h"
#include "cshapes/canon/coulomb_fmm.h"
#include "cshapes/support/error.h"
#include "cshapes/support/format.h"
#include "cshapes/mesh/mesh.h"
#include "cshapes/mesh/point_kdtree.h"
#include "cshapes/mesh/rigid_transform.h"
#include "cshapes/support/timing.h"

namespace cshapes {

CoulombScheme parse_coulomb_scheme(const std::string& name) {
  if (name == "paper") return CoulombScheme::Paper;
  if (name == "momentum") return CoulombScheme::Momentum;
  fail("unknown Coulomb scheme '", name, "'; known: paper, momentum");
}

std::string to_string(CoulombScheme scheme) {
  return scheme == CoulombScheme::Paper ? "paper" : "momentum";
}

FlattenPlane parse_flatten_plane(const std::string& name) {
  if (name == "spread") return FlattenPlane::Spread;
  if (name == "keep-mirror") return FlattenPlane::KeepMirror;
  throw Error("unknown flatten plane '" + name + "' (expected spread or keep-mirror)");
}

std::string to_string(FlattenPlane plane) { return plane == FlattenPlane::Spread ? "spread" : "keep-mirror"; }

CoulombStepRule parse_coulomb_step_rule(const std::string& name) {
  if (name == "max-edge") return CoulombStepRule::MaxEdge;
  if (name == "mean-edge") return CoulombStepRule::MeanEdge;
  if (name == "median-edge") return CoulombStepRule::MedianEdge;
  if (name == "fixed") return CoulombStepRule::Fixed;
  fail("unknown step rule '", name, "'; known: max-edge, mean-edge, median-edge, fixed");
}

std::string to_string(CoulombStepRule rule) {
  switch (rule) {
    case CoulombStepRule::MaxEdge:
      return "max-edge";
    case CoulombStepRule::MeanEdge:
      return "mean-edge";
    case CoulombStepRule::MedianEdge:
      return "median-edge";
    case CoulombStepRule::Fixed:
      return "fixed";
  }
  return "?";
}

StepGradient parse_step_gradient(const std::string& name) {
  if (name == "max") return StepGradient::Max;
  if (name == "mean") return StepGradient::Mean;
  fail("unknown step gradient statistic '", name, "'; known: max, mean");
}

std::string to_string(StepGradient statistic) {
  return statistic == StepGradient::Max ? "max" : "mean";
}

namespace {

// max_i ‖g_i‖ with one square root (sqrt is monotone, so this is exactly the max of the row norms).
double max_row_norm(const Points& G) {
  return std::sqrt(G.rowwise().squaredNorm().maxCoeff());
}

double mean_row_norm(const Points& G) {
  return G.rowwise().norm().mean();
}

double edge_scale(const Eigen::VectorXd& rest, CoulombStepRule rule) {
  if (rest.size() == 0) return 0;
  switch (rule) {
    case CoulombStepRule::MaxEdge:
      return rest.maxCoeff();
    case CoulombStepRule::MedianEdge: {
      std::vector<double> v(rest.data(), rest.data() + rest.size());
      auto mid = v.begin() + v.size() / 2;
      std::nth_element(v.begin(), mid, v.end());
      return *mid;
    }
    case CoulombStepRule::MeanEdge:
    case CoulombStepRule::Fixed:
      return rest.mean();
  }
  return rest.mean();
}

// Y's centroid and principal axes: the columns of `axes` by increasing spread, `variances` their mean squares.
struct PrincipalAxes {
  Eigen::RowVector3d centroid;
  Eigen::Matrix3d axes;
  Eigen::Vector3d variances;
};

PrincipalAxes principal_axes(const Points& Y) {
  PrincipalAxes p;
  p.centroid = Y.colwise().mean();
  Eigen::Matrix3d scatter = Eigen::Matrix3d::Zero();
  for (Index i = 0; i < Y.rows(); ++i) {
    const Eigen::Vector3d d = (Y.row(i) - p.centroid).transpose();
    scatter.noalias() += d * d.transpose();
  }
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eigen(scatter);
  p.axes = eigen.eigenvectors();
  p.variances = eigen.eigenvalues().cwiseMax(0.0) / static_cast<double>(std::max<Index>(Y.rows(), 1));
  return p;
}

// How far Y's reflection in the plane through its centroid normal to principal axis k lies from Y: the RMS
// distance from each reflected point to its nearest point of Y, over the RMS spread along the axis. 0 when
// the plane is a mirror of the point set; a form that is thin along the axis is not scored as symmetric for
// that alone. O(n log n).
double reflection_asymmetry(const Points& Y, const PointsKdTree& tree, const PrincipalAxes& p, int k) {
  const Eigen::RowVector3d normal = p.axes.col(k).transpose();
  std::vector<double> squared(static_cast<size_t>(Y.rows()));
#pragma omp parallel for schedule(static)
  for (Index i = 0; i < Y.rows(); ++i) {
    const Eigen::RowVector3d d = Y.row(i) - p.centroid;
    const Eigen::RowVector3d q = Y.row(i) - 2 * d.dot(normal) * normal;
    uint32_t nearest = 0;
    double distance2 = 0;
    tree.knnSearch(q.data(), 1, &nearest, &distance2);
    squared[static_cast<size_t>(i)] = distance2;
  }
  double sum = 0;
  for (const double v : squared) sum += v;
  const double spread = std::sqrt(p.variances[k]);
  return spread > 0 ? std::sqrt(sum / static_cast<double>(std::max<Index>(Y.rows(), 1))) / spread
                    : std::numeric_limits<double>::infinity();
}

// A plane is the start's mirror when the reflection in it moves the points less than across the other plane,
// and by less than this share of the spread along its normal (the RMS nearest-neighbour distance of the
// reflected points over the RMS spread). The bound lies between the scores of four-legged shapes' starts in
// their plane of largest spread and those of bipeds', hands' and spiders' on the tuning data; without it, the
// ratio of the two scores alone took a glued biped's start for a mirror (the scores:
// docs/coulomb-defaults.md, "The flatten's plane").
constexpr double kMirrorAsymmetry = 0.55;

// The flatten's pull (CoulombCanonOptions::flatten, flatten_plane), decided on the start.
class FlattenPull {
 public:
  FlattenPull() = default;  // no pull
  FlattenPull(const Points& start, double fraction, FlattenPlane plane) : fraction_(fraction) {
    if (!(fraction > 0)) return;
    if (plane == FlattenPlane::Spread || start.rows() < 4) {
      note_ = "pulled towards the plane of largest spread";
      return;
    }
    const PrincipalAxes p = principal_axes(start);
    const PointsKdAdaptor adaptor{start};
    PointsKdTree tree(3, adaptor, nanoflann::KDTreeSingleIndexAdaptorParams(16));
    tree.buildIndex();
    const double in = reflection_asymmetry(start, tree, p, 0);
    const double across = reflection_asymmetry(start, tree, p, 1);
    const std::string scores = "reflection asymmetry " + significant(in) + " in the plane of largest spread, " +
                               significant(across) + " across it";
    if (in < across && in < kMirrorAsymmetry) {
      fraction_ = 0;
      note_ = "not pulled: the start's plane of largest spread is its mirror (" + scores + ")";
    } else {
      note_ = "pulled towards the plane of largest spread (" + scores + ")";
    }
  }

  const std::string& note() const { return note_; }

  // Moves every row of Y towards the plane through its centroid spanned by its two directions of largest
  // spread, by `fraction` of its distance from that plane. O(n).
  void apply(Points& Y) const {
    if (!(fraction_ > 0)) return;
    const PrincipalAxes p = principal_axes(Y);
    const Eigen::RowVector3d normal = p.axes.col(0).transpose();  // least spread
    for (Index i = 0; i < Y.rows(); ++i) Y.row(i) -= fraction_ * (Y.row(i) - p.centroid).dot(normal) * normal;
  }

 private:
  double fraction_ = 0;
  std::string note_;
};

void check_options(const CoulombCanonOptions& o) {
  using namespace coulomb_limits;
  check_limit(kStepFactor, o.step_factor, "coulomb");
  check_limit(kFixedStep, o.fixed_step, "coulomb");
  check_limit(kCoulombSteps, o.coulomb_steps, "coulomb");
  check_limit(kMoveLimit, o.move_limit, "coulomb");
  check_limit(kTearFraction, o.tear_fraction, "coulomb");
  check_limit(kTearAfter, o.tear_after, "coulomb");
  check_limit(kTearTimes, o.tear_times, "coulomb");
  check_limit(kTearInterval, o.tear_interval, "coulomb");
  check_limit(kMaxIterations, o.max_iterations, "coulomb");
  check_limit(kWindow, o.stop_window, "coulomb");
  check_limit(kTolerance, o.stop_tolerance, "coulomb");
  check_limit(kMomentum, o.momentum, "coulomb");
  check_limit(kStallWindows, o.stall_windows, "coulomb");
  check_limit(kAccuracy, o.energy.accuracy, "coulomb");
  check_limit(kStartLandmarks, static_cast<double>(o.start_landmarks), "coulomb");
  check_limit(kFlatten, o.flatten, "coulomb");
  check_limit(kBridgeDetour, o.bridge_detour, "coulomb");
  check_limit(kFmmRebuildEvery, o.fmm_rebuild_every, "coulomb");
  CSHAPES_REQUIRE(o.result_accuracy > 0, "coulomb: result_accuracy must be > 0, got ", o.result_accuracy);
}

}  // namespace

namespace {

// The least relaxation factor of a stalled iteration: ω = 1/8 takes 8 iterations for one of T's steps.
constexpr double kSmallestRelaxation = 0.125;

// One run of the iteration from its start to convergence (or max_iterations): the state an outer iteration
// hands to the next.
class CoulombRun {
 public:
  // pre_torn: rows of E removed before the start is made (the bridges of a first run), counted as torn.
  CoulombRun(const Points& X0, const Edges& E, const CoulombCanonOptions& options,
             const Eigen::VectorXd& rest_lengths, WallClock::time_point start,
             const std::vector<Index>& pre_torn = {})
      : X0_(X0),
        E_(E),
        o_(options),
        start_(start),
        n_(X0.rows()),
        momentum_(options.scheme == CoulombScheme::Momentum),
        tearing_(options.tear_fraction > 0 && options.tear_times > 0),
        edges_(E),
        rest_(rest_lengths.size() ? rest_lengths : edge_lengths(X0, E)) {
    CSHAPES_REQUIRE(rest_.size() == E.rows(), "coulomb: ", rest_.size(), " rest lengths for ", E.rows(),
                    " edges");
    projection_ = std::make_unique<MetricProjection>(n_, edges_, rest_, o_.projection);
    scale_ = edge_scale(rest_, o_.step_rule);
    fixed_c_ = o_.fixed_step;
    next_tear_ = o_.tear_after;
    original_row_.resize(E.rows());
    std::iota(original_row_.begin(), original_row_.end(), Index(0));
    result_.torn_vertices = Eigen::VectorXd::Zero(n_);
    if (!pre_torn.empty()) remove_edges(pre_torn);
    CoulombStartResult start_at = coulomb_start(X0, edges_, o_.start, o_.start_landmarks);
    result_.start = start_at.note;
    // All work arrays are allocated once: an iteration at 5,000 vertices takes a few milliseconds, and fresh
    // n×3 matrices (120 kB, above malloc's mmap threshold) would be mapped and faulted in every time.
    X_ = std::move(start_at.X);
    flatten_ = FlattenPull(X_, o_.flatten, o_.flatten_plane);
    result_.flatten_plane = flatten_.note();
    X_prev_ = X_;
    Y_.resize(n_, 3);
    Y_extrapolated_.resize(momentum_ ? n_ : 0, 3);
    snapshot_ = X_;
    result_.history.reserve(static_cast<size_t>(std::min(o_.max_iterations, 100000)));
  }

  // Rows of E torn so far (the pre-torn ones first), in order.
  const std::vector<Index>& torn_rows() const { return torn_rows_; }

  CoulombCanonResult run() {
    int t = 0;
    for (t = 1; t <= o_.max_iterations; ++t)
      if (iterate(t)) {
        result_.converged = true;
        break;
      }
    finish(t);
    return std::move(result_);
  }

 private:
  // Outer iteration t: momentum's extrapolation, the Coulomb steps, the flattening, the projection, the rigid
  // alignment, the stopping test and the tears; its record into the history. Returns whether it converged.
  bool iterate(int t) {
    CoulombIterationRecord record;
    record.iteration = t;
    double beta = 0;
    if (momentum_) {
      beta = std::min(momentum_cap_, (since_restart_ - 1.0) / (since_restart_ + 2.0));
      Y_.noalias() = X_ + beta * (X_ - X_prev_);
      Y_extrapolated_ = Y_;
    }
    coulomb_steps(t, record);
    flatten_.apply(Y_);
    // The violation is measured inside the projection's pass (rigid motion below does not change it).
    RelativeViolation violation;
    projection_->project(Y_, &violation);
    if (!Y_.allFinite())
      fail("coulomb: non-finite coordinates at iteration ", t, " (scheme ", to_string(o_.scheme), ", step ",
           record.step, "); try --scheme paper or a smaller --step-factor");
    if (o_.remove_rigid_motion) rigid_align_in_place(Y_, X_);
    // Relaxed (after stalls without momentum): X + ω (T(X) − X) has the fixed points of T and damps its
    // oscillations.
    if (relaxation_ < 1) Y_ = X_ + relaxation_ * (Y_ - X_);
    bool restart = false;
    if (momentum_) {
      // Gradient-mapping restart: the step from the extrapolated point goes back against the momentum.
      restart = ((Y_extrapolated_ - Y_).cwiseProduct(Y_ - X_)).sum() > 0;
    }
    X_prev_.swap(X_);
    X_.swap(Y_);
    since_restart_ = restart ? 1 : since_restart_ + 1;
    record.momentum = beta;
    record.relaxation = relaxation_;
    record.mean_violation = violation.mean;
    record.max_violation = violation.max;

    // Stopping on the change of the shape over a window, after rigid alignment.
    bool converged = false;
    if (t - snapshot_iteration_ >= o_.stop_window) {
      const double diagonal = std::max(bbox_diagonal(X_), 1e-300);
      shape_change_ = rigid_rms_distance(X_, snapshot_) / diagonal;
      snapshot_ = X_;
      snapshot_iteration_ = t;
      // Relaxed by ω, the iteration moves ω times as far: the test is on the change the map itself makes. The
      // last iteration's own change must be as small, or a cycle whose period divides the window would pass.
      const double limit = o_.stop_tolerance * relaxation_;
      converged = shape_change_ < limit && rigid_rms_distance(X_, X_prev_) / diagonal < limit;
      if (momentum_) watch_for_stall();
    }
    const bool tear_pending = tearing_ && tears_done_ < o_.tear_times;
    if (tear_pending && (t >= next_tear_ || converged)) {
      // Converged before T: nothing would change until T, so tearing now gives the same result sooner.
      tear(t);
      converged = false;
    }
    record.torn_edges = static_cast<int>(torn_rows_.size());
    record.shape_change = shape_change_;
    record.seconds = seconds_since(start_);
    result_.history.push_back(record);
    if (o_.progress) o_.progress("coulomb", t, o_.max_iterations);
    return converged;
  }

  // The momentum scheme's safeguard, at the end of each stopping window: a window whose shape change is not
  // the smallest since the last tear (or the start) counts as stalled; after stall_windows of them in a row
  // the momentum is dropped (the plain iteration), and at each such run after that the relaxation factor
  // halves (down to kSmallestRelaxation).
  void watch_for_stall() {
    if (o_.stall_windows <= 0) return;
    if (shape_change_ < smallest_change_) {
      smallest_change_ = shape_change_;
      stalled_windows_ = 0;
      return;
    }
    if (++stalled_windows_ < o_.stall_windows) return;
    if (momentum_cap_ > 0)
      momentum_cap_ = 0;
    else
      relaxation_ = std::max(relaxation_ / 2, kSmallestRelaxation);
    stalled_windows_ = 0;
    smallest_change_ = shape_change_;
    since_restart_ = 1;
    X_prev_ = X_;
  }

  // The iteration's m Coulomb steps (eq. 4) into Y_, from X_ (plain scheme) or from the extrapolated Y_.
  void coulomb_steps(int t, CoulombIterationRecord& record) {
    for (int s = 0; s < o_.coulomb_steps; ++s) {
      // The plain scheme's first step starts at X itself: Y = X − c∇E(X) in one pass, no copy of X first.
      const bool from_x = s == 0 && !momentum_;
      const CoulombEvaluation eval = coulomb_energy_gradient(from_x ? X_ : Y_, o_.energy, &fmm_tree_);
      if (s == 0) record.energy = eval.energy;
      const double gmax = max_row_norm(eval.gradient);
      CSHAPES_REQUIRE(std::isfinite(gmax), "coulomb: non-finite Coulomb gradient at iteration ", t,
                      " (coincident or diverging vertices?)");
      const double g = o_.step_gradient == StepGradient::Max ? gmax : mean_row_norm(eval.gradient);
      double c = 0;
      if (g > 0) {
        if (o_.step_rule == CoulombStepRule::Fixed) {
          if (fixed_c_ == 0) fixed_c_ = o_.step_factor * scale_ / g;
          c = fixed_c_;
        } else {
          // Step rule after eq. (4): the fastest vertex moves step_factor · (edge scale).
          c = o_.step_factor * scale_ / g;
        }
      }
      // eq. (4), each vertex's move held within its move limit (CoulombCanonOptions::move_limit).
      if (from_x) Y_ = X_;
      const Eigen::VectorXd& limit = move_limits();
      double largest = 0;
      int limited = 0;
      for (Index i = 0; i < n_; ++i) {
        const double move = c * eval.gradient.row(i).norm();
        const double factor = move > limit[i] ? limit[i] / move : 1.0;
        limited += factor < 1;
        largest = std::max(largest, factor * move);
        Y_.row(i) -= (factor * c) * eval.gradient.row(i);
      }
      record.step = c;
      record.max_move = largest;
      record.limited_moves = limited;
    }
  }

  // Per vertex, the longest Coulomb move allowed: move_limit × the rest length of its shortest remaining
  // edge (infinity without a limit or without edges). Computed once per edge graph (again after a tear).
  const Eigen::VectorXd& move_limits() {
    if (move_limit_.size() == n_) return move_limit_;
    move_limit_ = Eigen::VectorXd::Constant(n_, std::numeric_limits<double>::infinity());
    if (!(o_.move_limit > 0)) return move_limit_;
    for (Index e = 0; e < edges_.rows(); ++e)
      for (int side = 0; side < 2; ++side)
        move_limit_[edges_(e, side)] = std::min(move_limit_[edges_(e, side)], o_.move_limit * rest_[e]);
    return move_limit_;
  }

  // One tear at `iteration`: the share of the edges the guard allows, by deviation, leaves the edge graph
  // (and the projection); momentum and the stopping window start again.
  void tear(int iteration) {
    const double share = o_.tear_fraction / o_.tear_times;
    const Index count = static_cast<Index>(std::ceil(share * static_cast<double>(E_.rows())));
    remove_edges(select_edges_to_tear(X_, edges_, rest_, n_, count, o_.tear_guard));
    ++tears_done_;
    next_tear_ = iteration + o_.tear_interval;
    // The tear changes the fixed point: momentum built towards the old one would overshoot (it overflowed to
    // NaN in the prototype), and the stopping window starts again.
    X_prev_ = X_;
    since_restart_ = 1;
    snapshot_ = X_;
    snapshot_iteration_ = iteration;
    smallest_change_ = std::numeric_limits<double>::infinity();
    stalled_windows_ = 0;
  }

  // Removes the edges `chosen` (rows of edges_) from the edge graph and the projection, recording them as
  // torn.
  void remove_edges(const std::vector<Index>& chosen) {
    std::vector<char> remove(edges_.rows(), 0);
    for (Index e : chosen) {
      remove[e] = 1;
      torn_rows_.push_back(original_row_[e]);
      result_.torn_vertices(edges_(e, 0)) = 1;
      result_.torn_vertices(edges_(e, 1)) = 1;
    }
    Edges kept(edges_.rows() - static_cast<Index>(chosen.size()), 2);
    Eigen::VectorXd kept_rest(kept.rows());
    std::vector<Index> kept_original;
    kept_original.reserve(kept.rows());
    Index k = 0;
    for (Index e = 0; e < edges_.rows(); ++e) {
      if (remove[e]) continue;
      kept.row(k) = edges_.row(e);
      kept_rest(k) = rest_(e);
      kept_original.push_back(original_row_[e]);
      ++k;
    }
    edges_ = std::move(kept);
    rest_ = std::move(kept_rest);
    original_row_ = std::move(kept_original);
    projection_ = std::make_unique<MetricProjection>(n_, edges_, rest_, o_.projection);
    move_limit_.resize(0);  // the shortest edges may have changed
  }

  // The result after the last iteration t: the energy at the result's accuracy, the violation, the quality,
  // the edges left and torn.
  void finish(int t) {
    result_.iterations = std::min(t, o_.max_iterations);
    result_.stop_reason = result_.converged ? "converged" : "max_iterations";
    if (o_.progress) o_.progress("coulomb", o_.max_iterations, o_.max_iterations);
    CoulombOptions final_energy = o_.energy;
    final_energy.accuracy = std::min(o_.energy.accuracy, o_.result_accuracy);
    result_.energy = coulomb_energy_gradient(X_, final_energy).energy;
    result_.violation = metric_violation(X_, edges_, rest_);
    std::vector<bool> torn_flags(E_.rows(), false);
    for (Index e : torn_rows_) torn_flags[e] = true;
    result_.quality = form_quality(X0_, E_, X_, &torn_flags);
    if (!result_.converged) {
      // A form that stopped at the cap is an iterate, not the fixed point: its verdict says so.
      std::string why = " before its first shape-change check";
      if (!(o_.stop_tolerance > 0))
        why = " (no stopping test: a tolerance of 0 runs every iteration)";
      else if (shape_change_ >= 0)
        why = " with the shape still changing by " + significant(100 * shape_change_) +
              "% of its bbox diagonal over " + std::to_string(o_.stop_window) + " iterations (converged below " +
              significant(100 * o_.stop_tolerance * relaxation_) + "%)";
      result_.not_converged =
          "not converged: stopped at the iteration cap of " + std::to_string(o_.max_iterations) + why;
      fail_form_quality(result_.quality, result_.not_converged);
    }
    result_.X = std::move(X_);
    result_.edges = std::move(edges_);
    result_.rest_lengths = std::move(rest_);
    result_.torn_edges.resize(static_cast<Index>(torn_rows_.size()), 2);
    for (size_t k = 0; k < torn_rows_.size(); ++k)
      result_.torn_edges.row(static_cast<Index>(k)) = E_.row(torn_rows_[k]);
    result_.seconds = seconds_since(start_);
  }

  const Points& X0_;
  const Edges& E_;
  const CoulombCanonOptions& o_;
  const WallClock::time_point start_;
  const Index n_;
  const bool momentum_, tearing_;
  CoulombCanonResult result_;
  Edges edges_;                  // the edges left
  Eigen::VectorXd rest_;         // their rest lengths
  std::vector<Index> original_row_;  // per edge left: its row in E
  std::vector<Index> torn_rows_;     // rows of E torn, in order
  std::unique_ptr<MetricProjection> projection_;
  CoulombFmmTree fmm_tree_{o_.fmm_rebuild_every};  // the fast summation's, kept between iterations
  FlattenPull flatten_;
  double scale_ = 0, fixed_c_ = 0;
  int tears_done_ = 0, next_tear_ = 0;
  Points X_, X_prev_, Y_, Y_extrapolated_, snapshot_;
  int snapshot_iteration_ = 0;
  Eigen::VectorXd move_limit_;  // move_limits(), for the current edges
  double momentum_cap_ = o_.momentum;  // lowered by watch_for_stall
  double relaxation_ = 1;              // ω, lowered by watch_for_stall once the momentum is gone
  double smallest_change_ = std::numeric_limits<double>::infinity();  // since the last tear
  int stalled_windows_ = 0;
  int since_restart_ = 1;  // Nesterov's counter: β = (k−1)/(k+2), 0 right after a (re)start
  double shape_change_ = -1;
};

}  // namespace

CoulombCanonResult coulomb_canonical_form(const Points& X0, const Edges& E,
                                          const CoulombCanonOptions& options,
                                          const Eigen::VectorXd& rest_lengths) {
  const WallClock::time_point start = WallClock::now();
  check_options(options);
  const Index n = X0.rows();
  CSHAPES_REQUIRE(n >= 2, "coulomb: need at least 2 vertices, got ", n);
  CSHAPES_REQUIRE(X0.allFinite(), "coulomb: the input coordinates contain NaN or infinity");
  CSHAPES_REQUIRE(E.rows() > 0, "coulomb: the edge graph is empty (a mesh without faces needs a kNN graph)");
  // A landmark MDS start lies in its own frame (canon/coulomb_start.h), so the iteration does not depend on the
  // input's orientation; the finished form is turned onto the input (rotation, translation, and a reflection
  // where the embedding came out mirrored), so that it is seen in the input's pose.
  auto in_input_frame = [&](CoulombCanonResult r) {
    if (options.start == CoulombStart::LandmarkMds && r.X.rows() == n && r.X.allFinite())
      r.X = best_rigid_transform(r.X, X0, /*determinant=*/0).apply(r.X);
    return r;
  };
  CoulombRun first(X0, E, options, rest_lengths, start);
  CoulombCanonResult result = first.run();
  if (!(options.bridge_detour > 0) || options.start == CoulombStart::Input || first.torn_rows().empty())
    return in_input_frame(std::move(result));
  const std::vector<Index> bridges =
      torn_bridges(X0, E, first.torn_rows(), options.bridge_detour * bbox_diagonal(X0));
  if (bridges.empty()) return in_input_frame(std::move(result));
  // Again from the embedding of the graph without the bridges, which stay torn from the first iteration; the
  // first run's iterations stay in the history (numbered on), so that the cost is seen.
  CoulombCanonResult again = CoulombRun(X0, E, options, rest_lengths, start, bridges).run();
  for (CoulombIterationRecord& record : again.history) record.iteration += result.iterations;
  result.history.insert(result.history.end(), again.history.begin(), again.history.end());
  again.history = std::move(result.history);
  again.iterations += result.iterations;
  again.start += "; again after the first run tore " + std::to_string(bridges.size()) +
                 (bridges.size() == 1 ? " bridge" : " bridges") + " (torn edges whose ends lie more than " +
                 significant(options.bridge_detour) +
                 " bbox diagonals, and more than their crack is long, apart along the other edges)";
  return in_input_frame(std::move(again));
}

}  // namespace cshapes
