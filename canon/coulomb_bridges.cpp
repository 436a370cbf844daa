#include "cshapes/canon/coulomb_bridges.h"

#include <algorithm>
#include <cmath>
#include <functional>
#include <numeric>
#include <queue>
#include <utility>

#include "cshapes/support/error.h"

namespace cshapes {

namespace {

// Disjoint sets of vertices (union by size, path halving).
class VertexSets {
 public:
  explicit VertexSets(Index n) : parent_(static_cast<size_t>(n)), size_(static_cast<size_t>(n), 1) {
    std::iota(parent_.begin(), parent_.end(), Index(0));
  }
  Index find(Index v) {
    while (parent_[static_cast<size_t>(v)] != v) {
      parent_[static_cast<size_t>(v)] = parent_[static_cast<size_t>(parent_[static_cast<size_t>(v)])];
      v = parent_[static_cast<size_t>(v)];
    }
    return v;
  }
  void join(Index a, Index b) {
    a = find(a);
    b = find(b);
    if (a == b) return;
    if (size_[static_cast<size_t>(a)] < size_[static_cast<size_t>(b)]) std::swap(a, b);
    parent_[static_cast<size_t>(b)] = a;
    size_[static_cast<size_t>(a)] += size_[static_cast<size_t>(b)];
  }

 private:
  std::vector<Index> parent_, size_;
};

}  // namespace

std::vector<Index> torn_bridges(const Points& X0, const Edges& E, const std::vector<Index>& torn,
                                double min_detour) {
  CSHAPES_REQUIRE(min_detour > 0, "torn_bridges: min_detour must be > 0, got ", min_detour);
  const Index n = X0.rows();
  if (torn.empty()) return {};
  std::vector<char> removed(static_cast<size_t>(E.rows()), 0);
  for (Index e : torn) {
    CSHAPES_REQUIRE(e >= 0 && e < E.rows(), "torn_bridges: edge row ", e, " out of range 0..", E.rows() - 1);
    removed[static_cast<size_t>(e)] = 1;
  }
  Eigen::VectorXd length(E.rows());
  for (Index e = 0; e < E.rows(); ++e) length(e) = (X0.row(E(e, 0)) - X0.row(E(e, 1))).norm();
  Eigen::VectorXd sorted = length;
  std::nth_element(sorted.data(), sorted.data() + sorted.size() / 2, sorted.data() + sorted.size());
  const double median_edge = sorted(sorted.size() / 2);
  // Cracks: the torn edges joined through shared vertices, and how many each holds.
  VertexSets cracks(n);
  for (Index e : torn) cracks.join(E(e, 0), E(e, 1));
  std::vector<Index> crack_edges(static_cast<size_t>(n), 0);
  for (Index e : torn) ++crack_edges[static_cast<size_t>(cracks.find(E(e, 0)))];
  // Adjacency of the remaining edges (CSR), weighted by their lengths.
  std::vector<Index> offset(static_cast<size_t>(n) + 1, 0);
  for (Index e = 0; e < E.rows(); ++e)
    if (!removed[static_cast<size_t>(e)]) {
      ++offset[static_cast<size_t>(E(e, 0)) + 1];
      ++offset[static_cast<size_t>(E(e, 1)) + 1];
    }
  for (Index v = 0; v < n; ++v) offset[static_cast<size_t>(v) + 1] += offset[static_cast<size_t>(v)];
  std::vector<std::pair<Index, double>> adjacent(static_cast<size_t>(offset.back()));
  std::vector<Index> fill(offset.begin(), offset.end() - 1);
  for (Index e = 0; e < E.rows(); ++e) {
    if (removed[static_cast<size_t>(e)]) continue;
    const Index a = E(e, 0), b = E(e, 1);
    adjacent[static_cast<size_t>(fill[static_cast<size_t>(a)]++)] = {b, length(e)};
    adjacent[static_cast<size_t>(fill[static_cast<size_t>(b)]++)] = {a, length(e)};
  }
  // One Dijkstra per torn edge from one end, stopped when the other end is settled within the bound (not a
  // bridge) or nothing within the bound is left (a bridge); distances are reset through the vertices reached.
  std::vector<double> distance(static_cast<size_t>(n), INFINITY);
  std::vector<Index> reached;
  using Entry = std::pair<double, Index>;
  std::priority_queue<Entry, std::vector<Entry>, std::greater<Entry>> queue;
  std::vector<Index> bridges;
  for (Index e : torn) {
    const Index a = E(e, 0), b = E(e, 1);
    const double k = std::max(static_cast<double>(crack_edges[static_cast<size_t>(cracks.find(a))]),
                              kMinBridgeDetourEdges);
    const double bound = std::max(min_detour, k * median_edge);
    distance[static_cast<size_t>(a)] = 0;
    reached.push_back(a);
    queue.push({0.0, a});
    bool within = false;
    while (!queue.empty()) {
      const auto [d, v] = queue.top();
      queue.pop();
      if (d > distance[static_cast<size_t>(v)]) continue;
      if (v == b) {
        within = true;
        break;
      }
      for (Index j = offset[static_cast<size_t>(v)]; j < offset[static_cast<size_t>(v) + 1]; ++j) {
        const auto [u, w] = adjacent[static_cast<size_t>(j)];
        const double du = d + w;
        if (du > bound || !(du < distance[static_cast<size_t>(u)])) continue;
        if (std::isinf(distance[static_cast<size_t>(u)])) reached.push_back(u);
        distance[static_cast<size_t>(u)] = du;
        queue.push({du, u});
      }
    }
    if (!within) bridges.push_back(e);
    queue = {};
    for (Index v : reached) distance[static_cast<size_t>(v)] = INFINITY;
    reached.clear();
  }
  return bridges;
}

}  // namespace cshapes
