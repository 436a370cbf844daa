#include "canon/coulomb.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <memory>
#include <numeric>

#include <Eigen/Eigenvalues>

#include "core/error.h"
#include "core/mesh.h"
#include "core/timing.h"

namespace cshapes {

CoulombScheme parse_coulomb_scheme(const std::string& name) {
  if (name == "paper") return CoulombScheme::Paper;
  if (name == "momentum") return CoulombScheme::Momentum;
  fail("unknown Coulomb scheme '", name, "'; known: paper, momentum");
}

std::string to_string(CoulombScheme scheme) {
  return scheme == CoulombScheme::Paper ? "paper" : "momentum";
}

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

TearGuard parse_tear_guard(const std::string& name) {
  if (name == "vertex") return TearGuard::Vertex;
  if (name == "connected") return TearGuard::Connected;
  fail("unknown tear guard '", name, "'; known: vertex, connected");
}

std::string to_string(TearGuard guard) {
  return guard == TearGuard::Vertex ? "vertex" : "connected";
}

namespace {

// The edge graph during one tear: adjacency with edge ids, edges removed so far, and a bidirectional
// breadth-first search that tells whether two vertices are still joined.
class TearGraph {
 public:
  TearGraph(Index num_vertices, const Edges& E)
      : offsets_(num_vertices + 1, 0), removed_(E.rows(), 0), mark_(num_vertices, 0) {
    for (Index e = 0; e < E.rows(); ++e) {
      ++offsets_[E(e, 0) + 1];
      ++offsets_[E(e, 1) + 1];
    }
    for (Index i = 0; i < num_vertices; ++i) offsets_[i + 1] += offsets_[i];
    neighbor_.resize(offsets_.back());
    edge_.resize(offsets_.back());
    std::vector<int> fill(offsets_.begin(), offsets_.end() - 1);
    for (Index e = 0; e < E.rows(); ++e) {
      for (int side = 0; side < 2; ++side) {
        const int k = fill[E(e, side)]++;
        neighbor_[k] = E(e, 1 - side);
        edge_[k] = static_cast<int>(e);
      }
    }
  }

  void remove(Index e) { removed_[e] = 1; }
  void restore(Index e) { removed_[e] = 0; }

  // Whether a and b are joined by a path of edges not removed. Grows a search from each end, one vertex at a
  // time from the smaller frontier; stops when they meet or one side runs out, so it costs O(smaller side).
  bool joined(int a, int b) {
    if (a == b) return true;
    stamp_ += 2;  // marks stamp_ (side a) and stamp_ + 1 (side b): no clearing between searches
    if (stamp_ > std::numeric_limits<int>::max() - 2) {
      std::fill(mark_.begin(), mark_.end(), 0);
      stamp_ = 2;
    }
    std::vector<int>* queue[2] = {&queue_a_, &queue_b_};
    size_t head[2] = {0, 0};
    queue_a_.assign(1, a);
    queue_b_.assign(1, b);
    mark_[a] = stamp_;
    mark_[b] = stamp_ + 1;
    while (head[0] < queue_a_.size() && head[1] < queue_b_.size()) {
      const int side = queue_a_.size() - head[0] <= queue_b_.size() - head[1] ? 0 : 1;
      const int v = (*queue[side])[head[side]++];
      for (int k = offsets_[v]; k < offsets_[v + 1]; ++k) {
        if (removed_[edge_[k]]) continue;
        const int w = neighbor_[k];
        if (mark_[w] == stamp_ + 1 - side) return true;  // reached from the other side
        if (mark_[w] == stamp_ + side) continue;
        mark_[w] = stamp_ + side;
        queue[side]->push_back(w);
      }
    }
    return false;
  }

 private:
  std::vector<int> offsets_, neighbor_, edge_;
  std::vector<char> removed_;
  std::vector<int> mark_, queue_a_, queue_b_;
  int stamp_ = 0;
};

}  // namespace

std::vector<Index> select_edges_to_tear(const Points& X, const Edges& E, const Eigen::VectorXd& rest_lengths,
                                        Index num_vertices, Index count, TearGuard guard) {
  CSHAPES_REQUIRE(rest_lengths.size() == E.rows(), "tearing: ", rest_lengths.size(), " rest lengths for ",
                  E.rows(), " edges");
  std::vector<double> deviation(E.rows());
  for (Index e = 0; e < E.rows(); ++e)
    deviation[e] = std::abs((X.row(E(e, 0)) - X.row(E(e, 1))).norm() - rest_lengths(e));
  std::vector<Index> order(E.rows());
  std::iota(order.begin(), order.end(), Index(0));
  std::stable_sort(order.begin(), order.end(), [&](Index a, Index b) { return deviation[a] > deviation[b]; });
  std::vector<int> degree(num_vertices, 0);
  for (Index e = 0; e < E.rows(); ++e) {
    ++degree[E(e, 0)];
    ++degree[E(e, 1)];
  }
  const bool connected = guard == TearGuard::Connected;
  // Vertex: never leave a vertex without edges, a free charge drifting away (prototype). Connected: not with
  // one edge either (a flapping spike), nor cut off a pair or a patch, which drifts away just the same.
  const int min_degree = connected ? 2 : 1;
  std::unique_ptr<TearGraph> graph;
  if (connected && count > 0) graph = std::make_unique<TearGraph>(num_vertices, E);
  std::vector<Index> chosen;
  for (Index e : order) {
    if (static_cast<Index>(chosen.size()) >= count) break;
    const int i = E(e, 0), j = E(e, 1);
    if (degree[i] <= min_degree || degree[j] <= min_degree) continue;
    if (graph) {
      graph->remove(e);
      if (!graph->joined(i, j)) {
        graph->restore(e);  // a bridge of the remaining graph: tearing it would cut a part off
        continue;
      }
    }
    --degree[i];
    --degree[j];
    chosen.push_back(e);
  }
  return chosen;
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

// Moves every row of Y towards the plane through the centroid spanned by Y's two directions of largest
// spread, by `fraction` of its distance from that plane (CoulombCanonOptions::flatten). O(n).
void flatten_towards_plane(Points& Y, double fraction) {
  const Eigen::RowVector3d centroid = Y.colwise().mean();
  Eigen::Matrix3d scatter = Eigen::Matrix3d::Zero();
  for (Index i = 0; i < Y.rows(); ++i) {
    const Eigen::Vector3d d = (Y.row(i) - centroid).transpose();
    scatter.noalias() += d * d.transpose();
  }
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eigen(scatter);
  const Eigen::RowVector3d normal = eigen.eigenvectors().col(0).transpose();  // least spread
  for (Index i = 0; i < Y.rows(); ++i) Y.row(i) -= fraction * (Y.row(i) - centroid).dot(normal) * normal;
}

void check_options(const CoulombCanonOptions& o) {
  using namespace coulomb_limits;
  check_limit(kStepFactor, o.step_factor, "coulomb");
  check_limit(kFixedStep, o.fixed_step, "coulomb");
  check_limit(kCoulombSteps, o.coulomb_steps, "coulomb");
  check_limit(kTearFraction, o.tear_fraction, "coulomb");
  check_limit(kTearAfter, o.tear_after, "coulomb");
  check_limit(kTearTimes, o.tear_times, "coulomb");
  check_limit(kTearInterval, o.tear_interval, "coulomb");
  check_limit(kMaxIterations, o.max_iterations, "coulomb");
  check_limit(kWindow, o.stop_window, "coulomb");
  check_limit(kTolerance, o.stop_tolerance, "coulomb");
  check_limit(kMomentum, o.momentum, "coulomb");
  check_limit(kAccuracy, o.energy.accuracy, "coulomb");
  check_limit(kStartLandmarks, static_cast<double>(o.start_landmarks), "coulomb");
  check_limit(kFlatten, o.flatten, "coulomb");
  CSHAPES_REQUIRE(o.result_accuracy > 0, "coulomb: result_accuracy must be > 0, got ", o.result_accuracy);
}

}  // namespace

CoulombCanonResult coulomb_canonical_form(const Points& X0, const Edges& E,
                                          const CoulombCanonOptions& options,
                                          const Eigen::VectorXd& rest_lengths) {
  const WallClock::time_point start = WallClock::now();
  auto elapsed = [&] { return seconds_since(start); };
  check_options(options);
  const Index n = X0.rows();
  CSHAPES_REQUIRE(n >= 2, "coulomb: need at least 2 vertices, got ", n);
  CSHAPES_REQUIRE(X0.allFinite(), "coulomb: the input coordinates contain NaN or infinity");
  CSHAPES_REQUIRE(E.rows() > 0, "coulomb: the edge graph is empty (a mesh without faces needs a kNN graph)");

  CoulombCanonResult result;
  Edges edges = E;
  Eigen::VectorXd rest = rest_lengths.size() ? rest_lengths : edge_lengths(X0, E);
  CSHAPES_REQUIRE(rest.size() == E.rows(), "coulomb: ", rest.size(), " rest lengths for ", E.rows(),
                  " edges");
  auto projection = std::make_unique<MetricProjection>(n, edges, rest, options.projection);
  const double scale = edge_scale(rest, options.step_rule);
  double fixed_c = options.fixed_step;

  const bool momentum = options.scheme == CoulombScheme::Momentum;
  const bool tearing = options.tear_fraction > 0 && options.tear_times > 0;
  int tears_done = 0, next_tear = options.tear_after;
  std::vector<Index> torn_rows;  // row indices into the ORIGINAL E
  std::vector<Index> original_row(E.rows());
  std::iota(original_row.begin(), original_row.end(), Index(0));
  result.torn_vertices = Eigen::VectorXd::Zero(n);

  CoulombStartResult start_at = coulomb_start(X0, E, options.start, options.start_landmarks);
  result.start = start_at.note;

  // All work arrays are allocated once: an iteration at 5,000 vertices takes a few milliseconds, and fresh
  // n×3 matrices (120 kB, above malloc's mmap threshold) would be mapped and faulted in every time.
  Points X = std::move(start_at.X), X_prev = X, Y(n, 3), Y_extrapolated(momentum ? n : 0, 3);
  Points snapshot = X;
  int snapshot_iteration = 0;
  int since_restart = 1;  // Nesterov's counter: β = (k−1)/(k+2), 0 right after a (re)start
  double shape_change = -1;
  result.history.reserve(static_cast<size_t>(std::min(options.max_iterations, 100000)));

  auto tear_now = [&](int iteration) {
    const double share = options.tear_fraction / options.tear_times;
    const Index count = static_cast<Index>(std::ceil(share * static_cast<double>(E.rows())));
    std::vector<Index> chosen = select_edges_to_tear(X, edges, rest, n, count, options.tear_guard);
    std::vector<char> remove(edges.rows(), 0);
    for (Index e : chosen) {
      remove[e] = 1;
      torn_rows.push_back(original_row[e]);
      result.torn_vertices(edges(e, 0)) = 1;
      result.torn_vertices(edges(e, 1)) = 1;
    }
    Edges kept(edges.rows() - static_cast<Index>(chosen.size()), 2);
    Eigen::VectorXd kept_rest(kept.rows());
    std::vector<Index> kept_original;
    kept_original.reserve(kept.rows());
    Index k = 0;
    for (Index e = 0; e < edges.rows(); ++e) {
      if (remove[e]) continue;
      kept.row(k) = edges.row(e);
      kept_rest(k) = rest(e);
      kept_original.push_back(original_row[e]);
      ++k;
    }
    edges = std::move(kept);
    rest = std::move(kept_rest);
    original_row = std::move(kept_original);
    projection = std::make_unique<MetricProjection>(n, edges, rest, options.projection);
    ++tears_done;
    next_tear = iteration + options.tear_interval;
    // The tear changes the fixed point: momentum built towards the old one would overshoot (it overflowed to
    // NaN in the prototype), and the stopping window starts again.
    X_prev = X;
    since_restart = 1;
    snapshot = X;
    snapshot_iteration = iteration;
  };

  int t = 0;
  for (t = 1; t <= options.max_iterations; ++t) {
    CoulombIterationRecord record;
    record.iteration = t;
    double beta = 0;
    if (momentum) {
      beta = std::min(options.momentum, (since_restart - 1.0) / (since_restart + 2.0));
      Y.noalias() = X + beta * (X - X_prev);
      Y_extrapolated = Y;
    }
    for (int s = 0; s < options.coulomb_steps; ++s) {
      // The plain scheme's first step starts at X itself: Y = X − c∇E(X) in one pass, no copy of X first.
      const bool from_x = s == 0 && !momentum;
      const CoulombEvaluation eval = coulomb_energy_gradient(from_x ? X : Y, options.energy);
      if (s == 0) record.energy = eval.energy;
      const double gmax = max_row_norm(eval.gradient);
      CSHAPES_REQUIRE(std::isfinite(gmax), "coulomb: non-finite Coulomb gradient at iteration ", t,
                      " (coincident or diverging vertices?)");
      const double g = options.step_gradient == StepGradient::Max ? gmax : mean_row_norm(eval.gradient);
      double c = 0;
      if (g > 0) {
        if (options.step_rule == CoulombStepRule::Fixed) {
          if (fixed_c == 0) fixed_c = options.step_factor * scale / g;
          c = fixed_c;
        } else {
          // Step rule after eq. (4): the fastest vertex moves step_factor · (edge scale).
          c = options.step_factor * scale / g;
        }
      }
      // eq. (4)
      if (from_x)
        Y.noalias() = X - c * eval.gradient;
      else
        Y -= c * eval.gradient;
      record.step = c;
      record.max_move = c * gmax;
    }
    if (options.flatten > 0) flatten_towards_plane(Y, options.flatten);
    // The violation is measured inside the projection's pass (rigid motion below does not change it).
    RelativeViolation violation;
    projection->project(Y, &violation);
    if (!Y.allFinite())
      fail("coulomb: non-finite coordinates at iteration ", t, " (scheme ", to_string(options.scheme),
           ", step ", record.step, "); try --scheme paper or a smaller --step-factor");
    if (options.remove_rigid_motion) rigid_align_in_place(Y, X);
    bool restart = false;
    if (momentum) {
      // Gradient-mapping restart: the step from the extrapolated point goes back against the momentum.
      restart = ((Y_extrapolated - Y).cwiseProduct(Y - X)).sum() > 0;
    }
    X_prev.swap(X);
    X.swap(Y);
    since_restart = restart ? 1 : since_restart + 1;
    record.momentum = beta;

    record.mean_violation = violation.mean;
    record.max_violation = violation.max;

    // Stopping on the change of the shape over a window, after rigid alignment.
    bool converged = false;
    if (t - snapshot_iteration >= options.stop_window) {
      shape_change = rigid_rms_distance(X, snapshot) / std::max(bbox_diagonal(X), 1e-300);
      snapshot = X;
      snapshot_iteration = t;
      converged = shape_change < options.stop_tolerance;
    }
    const bool tear_pending = tearing && tears_done < options.tear_times;
    if (tear_pending && (t >= next_tear || converged)) {
      // Converged before T: nothing would change until T, so tearing now gives the same result sooner.
      tear_now(t);
      converged = false;
    }
    record.torn_edges = static_cast<int>(torn_rows.size());
    record.shape_change = shape_change;
    record.seconds = elapsed();
    result.history.push_back(record);
    if (options.progress) options.progress("coulomb", t, options.max_iterations);
    if (converged) {
      result.converged = true;
      break;
    }
  }
  result.iterations = std::min(t, options.max_iterations);
  result.stop_reason = result.converged ? "converged" : "max_iterations";
  if (options.progress) options.progress("coulomb", options.max_iterations, options.max_iterations);

  CoulombOptions final_energy = options.energy;
  final_energy.accuracy = std::min(options.energy.accuracy, options.result_accuracy);
  result.energy = coulomb_energy_gradient(X, final_energy).energy;
  result.violation = metric_violation(X, edges, rest);
  std::vector<bool> torn_flags(E.rows(), false);
  for (Index e : torn_rows) torn_flags[e] = true;
  result.quality = form_quality(X0, E, X, &torn_flags);
  result.X = std::move(X);
  result.edges = std::move(edges);
  result.rest_lengths = std::move(rest);
  result.torn_edges.resize(static_cast<Index>(torn_rows.size()), 2);
  for (size_t k = 0; k < torn_rows.size(); ++k)
    result.torn_edges.row(static_cast<Index>(k)) = E.row(torn_rows[k]);
  result.seconds = elapsed();
  return result;
}

}  // namespace cshapes
