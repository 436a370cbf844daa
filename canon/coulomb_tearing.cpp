#include "cshapes/canon/coulomb_tearing.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <memory>
#include <numeric>
#include <utility>

#include "cshapes/support/error.h"

namespace cshapes {

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

namespace {

// Whether point a comes before point b by its coordinates (x, then y, then z): the tie-break where the
// iteration must choose between equals, so that the choice does not depend on the numbering.
bool before_by_position(const Points& X, Index a, Index b) {
  for (int k = 0; k < 3; ++k)
    if (X(a, k) != X(b, k)) return X(a, k) < X(b, k);
  return false;
}

}  // namespace

std::vector<Index> select_edges_to_tear(const Points& X, const Edges& E, const Eigen::VectorXd& rest_lengths,
                                        Index num_vertices, Index count, TearGuard guard) {
  CSHAPES_REQUIRE(rest_lengths.size() == E.rows(), "tearing: ", rest_lengths.size(), " rest lengths for ",
                  E.rows(), " edges");
  std::vector<double> deviation(E.rows());
  for (Index e = 0; e < E.rows(); ++e)
    deviation[e] = std::abs((X.row(E(e, 0)) - X.row(E(e, 1))).norm() - rest_lengths(e));
  // By decreasing deviation; equal deviations by the positions of the edges' ends, not by their numbers.
  auto ends = [&](Index e) {
    const Index i = E(e, 0), j = E(e, 1);
    return before_by_position(X, j, i) ? std::make_pair(j, i) : std::make_pair(i, j);
  };
  auto position_order = [&](Index a, Index b) {
    const auto [a0, a1] = ends(a);
    const auto [b0, b1] = ends(b);
    if (before_by_position(X, a0, b0)) return true;
    if (before_by_position(X, b0, a0)) return false;
    return before_by_position(X, a1, b1);
  };
  std::vector<Index> order(E.rows());
  std::iota(order.begin(), order.end(), Index(0));
  std::sort(order.begin(), order.end(), [&](Index a, Index b) {
    if (deviation[a] != deviation[b]) return deviation[a] > deviation[b];
    return position_order(a, b);
  });
  std::vector<int> degree(num_vertices, 0);
  for (Index e = 0; e < E.rows(); ++e) {
    ++degree[E(e, 0)];
    ++degree[E(e, 1)];
  }
  const bool connected = guard == TearGuard::Connected;
  const double tie_floor = kTearMargin * (rest_lengths.size() ? rest_lengths.cwiseAbs().mean() : 0.0);
  // Vertex: never leave a vertex without edges, a free charge drifting away (prototype). Connected: not with
  // one edge either (a flapping spike), nor cut off a pair or a patch, which drifts away just the same.
  const int min_degree = connected ? 2 : 1;
  std::unique_ptr<TearGraph> graph;
  if (connected && count > 0) graph = std::make_unique<TearGraph>(num_vertices, E);
  std::vector<Index> chosen;
  for (Index e : order) {
    // Past `count`, the edges whose deviation lies within kTearMargin of the count-th one are torn with it,
    // so that the cut between torn and kept lies where the deviations differ by more than rounding could
    // change (not when the count-th deviation is itself at the rounding's level: undeformed edges are no
    // ties).
    if (static_cast<Index>(chosen.size()) >= count) {
      const double cut = count > 0 ? deviation[chosen[static_cast<size_t>(count - 1)]] : 0.0;
      if (!(cut > tie_floor) || deviation[e] < (1 - kTearMargin) * cut) break;
    }
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

}  // namespace cshapes
