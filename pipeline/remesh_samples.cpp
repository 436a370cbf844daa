#include "pipeline/remesh_samples.h"

#include <algorithm>
#include <functional>
#include <queue>
#include <unordered_map>
#include <utility>

#include "core/error.h"
#include "matching/nearest_neighbors.h"

namespace cshapes {

namespace {

// Whether every vertex of `targets` lies within graph distance `radius` of `source` along the edges of
// `graph` (lengths `length`, indexed by edge id): Dijkstra from the source, stopped past the radius or when
// every target is reached.
bool within_reach(int source, const std::vector<int>& targets, double radius, const Adjacency& graph,
                  const Eigen::VectorXd& length) {
  std::vector<int> left;
  for (int t : targets)
    if (t != source && std::find(left.begin(), left.end(), t) == left.end()) left.push_back(t);
  if (left.empty()) return true;
  std::unordered_map<int, double> distance{{source, 0.0}};
  using Entry = std::pair<double, int>;
  std::priority_queue<Entry, std::vector<Entry>, std::greater<Entry>> queue;
  queue.push({0.0, source});
  while (!queue.empty()) {
    const auto [d, v] = queue.top();
    queue.pop();
    if (d > distance[v]) continue;  // a stale entry
    left.erase(std::remove(left.begin(), left.end(), v), left.end());
    if (left.empty()) return true;
    for (int k = graph.offsets[v]; k < graph.offsets[v + 1]; ++k) {
      const int w = graph.neighbors[k];
      const double through = d + length[graph.edge_ids[k]];
      if (through > radius) continue;
      const auto found = distance.find(w);
      if (found != distance.end() && found->second <= through) continue;
      distance[w] = through;
      queue.push({through, w});
    }
  }
  return false;
}

}  // namespace

RemeshSamples carry_to_remesh(const Mesh& input, const Mesh& remesh, const std::vector<int>& vertices) {
  RemeshSamples out;
  out.vertices = vertices;
  Points P(static_cast<Index>(vertices.size()), 3);
  for (size_t k = 0; k < vertices.size(); ++k) {
    CSHAPES_REQUIRE(vertices[k] >= 0 && vertices[k] < input.num_vertices(), "carry_to_remesh: vertex ",
                    vertices[k], " is not one of the input's ", input.num_vertices());
    P.row(static_cast<Index>(k)) = input.V.row(vertices[k]);
  }
  out.at = locate_on_surface(remesh.V, remesh.F, P);
  if (vertices.empty()) return out;

  const double diagonal = finite_bbox_diagonal(input.V);
  out.max_distance = out.at.distance.maxCoeff() / diagonal;
  out.mean_distance = out.at.distance.mean() / diagonal;

  // Off its part: the located triangle's corners, taken back to the input, out of reach along its edges.
  const Edges E = mesh_edges(input.F);
  const Eigen::VectorXd length = edge_lengths(input.V, E);
  const Adjacency graph = adjacency(input.num_vertices(), E);
  Eigen::VectorXi back;  // per remesh vertex: its nearest input vertex
  Eigen::VectorXd squared;
  NearestNeighbors(input.V).nearest_all(remesh.V, back, squared);
  int off_part = 0;
#pragma omp parallel for schedule(dynamic, 16) reduction(+ : off_part)
  for (Index k = 0; k < P.rows(); ++k) {
    const int v = vertices[static_cast<size_t>(k)];
    const int f = out.at.face[k];
    double longest = 0;
    for (int c = 0; c < 3; ++c)
      longest =
          std::max(longest, (remesh.V.row(remesh.F(f, c)) - remesh.V.row(remesh.F(f, (c + 1) % 3))).norm());
    double longest_here = 0;
    for (int e = graph.offsets[v]; e < graph.offsets[v + 1]; ++e)
      longest_here = std::max(longest_here, length[graph.edge_ids[e]]);
    const double radius = 2 * (out.at.distance[k] + longest) + longest_here;
    const std::vector<int> corners = {back[remesh.F(f, 0)], back[remesh.F(f, 1)], back[remesh.F(f, 2)]};
    if (!within_reach(v, corners, radius, graph, length)) ++off_part;
  }
  out.off_part = off_part;
  return out;
}

}  // namespace cshapes
