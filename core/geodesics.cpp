#include "core/geodesics.h"

#include <atomic>
#include <limits>
#include <queue>

#include "core/error.h"

namespace cshapes {

GeodesicMethod parse_geodesic_method(const std::string& name) {
  if (name == "graph") return GeodesicMethod::Graph;
  fail("unknown geodesic method '", name, "'; known: graph");
}

std::string to_string(GeodesicMethod method) {
  switch (method) {
    case GeodesicMethod::Graph:
      return "graph";
  }
  return "?";
}

Eigen::VectorXd dijkstra(Index num_vertices, const Adjacency& adj, const Eigen::VectorXd& edge_weights,
                         const std::vector<int>& sources) {
  const double inf = std::numeric_limits<double>::infinity();
  Eigen::VectorXd dist = Eigen::VectorXd::Constant(num_vertices, inf);
  using Item = std::pair<double, int>;
  std::priority_queue<Item, std::vector<Item>, std::greater<Item>> queue;
  for (int s : sources) {
    CSHAPES_REQUIRE(s >= 0 && s < num_vertices, "geodesics: source vertex ", s, " out of range 0..",
                    num_vertices - 1);
    dist[s] = 0;
    queue.emplace(0.0, s);
  }
  while (!queue.empty()) {
    auto [d, i] = queue.top();
    queue.pop();
    if (d > dist[i]) continue;
    for (int k = adj.offsets[i]; k < adj.offsets[i + 1]; ++k) {
      int j = adj.neighbors[k];
      double nd = d + edge_weights[adj.edge_ids[k]];
      if (nd < dist[j]) {
        dist[j] = nd;
        queue.emplace(nd, j);
      }
    }
  }
  return dist;
}

Eigen::VectorXd geodesic_distances(const Mesh& mesh, const std::vector<int>& sources,
                                   const GeodesicOptions& options) {
  switch (options.method) {
    case GeodesicMethod::Graph: {
      Edges E = mesh_edges(mesh.F);
      return dijkstra(mesh.num_vertices(), adjacency(mesh.num_vertices(), E), edge_lengths(mesh.V, E), sources);
    }
  }
  fail("geodesics: unsupported method");
}

DistanceMatrix all_pairs_geodesics(const Mesh& mesh, const GeodesicOptions& options) {
  const Index n = mesh.num_vertices();
  require_memory(distance_matrix_bytes(n), "all-pairs geodesics on " + std::to_string(n) + " vertices");
  DistanceMatrix D(n, n);
  Edges E = mesh_edges(mesh.F);
  Adjacency adj = adjacency(n, E);
  Eigen::VectorXd w = edge_lengths(mesh.V, E);
  std::atomic<Index> done{0};
#pragma omp parallel for schedule(dynamic, 16)
  for (Index s = 0; s < n; ++s) {
    D.col(s) = dijkstra(n, adj, w, {static_cast<int>(s)}).cast<float>();
    Index finished = ++done;
    if (options.progress && finished % 64 == 0) {
#pragma omp critical(cshapes_progress)
      options.progress("geodesics", static_cast<double>(finished), static_cast<double>(n));
    }
  }
  // Symmetrise in place, block by block, without a second n×n matrix.
  for (Index j = 0; j < n; ++j)
    for (Index i = j + 1; i < n; ++i) {
      float m = 0.5f * (D(i, j) + D(j, i));
      D(i, j) = D(j, i) = m;
    }
  if (options.progress) options.progress("geodesics", static_cast<double>(n), static_cast<double>(n));
  return D;
}

}  // namespace cshapes
