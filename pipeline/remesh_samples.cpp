#include "cshapes/pipeline/remesh_samples.h"

#include <algorithm>
#include <functional>
#include <limits>
#include <queue>
#include <unordered_map>
#include <utility>

#include "cshapes/support/error.h"
#include "cshapes/matching/nearest_neighbors.h"
#include "cshapes/pipeline/experiment_kit.h"

namespace cshapes {

namespace {

// How far along the input's surface a located triangle's corners may lie and still be the sample's part, in
// mean remesh edges (plus twice the sample's distance to the triangle and twice its longest input edge).
// Narrower folds than that (lips, eyelids, between fingers: 3-10 units on KIDS at 5,000 vertices, edge 1.3)
// are below the remesh's resolution; the other part of a contact is much farther (an arm against the
// body, 40-57 units there).
constexpr double kPartReachEdges = 10;

// The input's edge graph, and each remesh vertex taken back to the input (its nearest input vertex).
struct PartGraph {
  Adjacency graph;
  Eigen::VectorXd length;                         // per edge id
  Eigen::VectorXi back;                           // per remesh vertex: the nearest input vertex
  std::vector<std::vector<int>> remesh_vertices;  // per input vertex: the remesh vertices taken back to it
  std::vector<std::vector<int>> remesh_faces;     // per remesh vertex: its faces
};

PartGraph part_graph(const Mesh& input, const Mesh& remesh) {
  PartGraph g;
  const Edges E = mesh_edges(input.F);
  g.length = edge_lengths(input.V, E);
  g.graph = adjacency(input.num_vertices(), E);
  Eigen::VectorXd squared;
  NearestNeighbors(input.V).nearest_all(remesh.V, g.back, squared);
  g.remesh_vertices.resize(static_cast<size_t>(input.num_vertices()));
  for (Index r = 0; r < g.back.size(); ++r) g.remesh_vertices[g.back[r]].push_back(static_cast<int>(r));
  g.remesh_faces.resize(static_cast<size_t>(remesh.num_vertices()));
  for (Index f = 0; f < remesh.num_faces(); ++f)
    for (int c = 0; c < 3; ++c) g.remesh_faces[remesh.F(f, c)].push_back(static_cast<int>(f));
  return g;
}

// Input vertices within graph distance `radius` of `source` along the input's edges (Dijkstra, bounded),
// with their distances. stop_when_reached: return as soon as every vertex of it is reached (then the map
// holds only what was settled so far).
std::unordered_map<int, double> reach(int source, double radius, const PartGraph& g,
                                      const std::vector<int>& stop_when_reached = {}) {
  std::vector<int> left = stop_when_reached;
  std::unordered_map<int, double> distance{{source, 0.0}};
  std::unordered_map<int, double> settled;
  using Entry = std::pair<double, int>;
  std::priority_queue<Entry, std::vector<Entry>, std::greater<Entry>> queue;
  queue.push({0.0, source});
  while (!queue.empty()) {
    const auto [d, v] = queue.top();
    queue.pop();
    if (settled.count(v)) continue;  // a stale entry
    settled[v] = d;
    if (!left.empty()) {
      left.erase(std::remove(left.begin(), left.end(), v), left.end());
      if (left.empty()) return settled;
    }
    for (int k = g.graph.offsets[v]; k < g.graph.offsets[v + 1]; ++k) {
      const int w = g.graph.neighbors[k];
      const double through = d + g.length[g.graph.edge_ids[k]];
      if (through > radius || settled.count(w)) continue;
      const auto found = distance.find(w);
      if (found != distance.end() && found->second <= through) continue;
      distance[w] = through;
      queue.push({through, w});
    }
  }
  return settled;
}

bool on_part(const Faces& F, int f, const Eigen::VectorXi& back,
             const std::unordered_map<int, double>& reached) {
  for (int c = 0; c < 3; ++c)
    if (!reached.count(back[F(f, c)])) return false;
  return true;
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

  // The closest triangle on the sample's own part of the surface (see the header).
  const PartGraph g = part_graph(input, remesh);
  const double remesh_edge = edge_lengths(remesh.V, mesh_edges(remesh.F)).mean();
  int relocated = 0, off_part = 0;
#pragma omp parallel for schedule(dynamic, 16) reduction(+ : relocated, off_part)
  for (Index k = 0; k < P.rows(); ++k) {
    const int v = vertices[static_cast<size_t>(k)];
    double longest_here = 0;
    for (int e = g.graph.offsets[v]; e < g.graph.offsets[v + 1]; ++e)
      longest_here = std::max(longest_here, g.length[g.graph.edge_ids[e]]);
    const double radius = 2 * out.at.distance[k] + kPartReachEdges * remesh_edge + 2 * longest_here;
    const int f = out.at.face[k];
    const std::vector<int> corners = {g.back[remesh.F(f, 0)], g.back[remesh.F(f, 1)], g.back[remesh.F(f, 2)]};
    // Not on the part, the search never stopped early: `reached` is everything within the radius.
    const std::unordered_map<int, double> reached = reach(v, radius, g, corners);
    if (on_part(remesh.F, f, g.back, reached)) continue;
    // Closest to another part: the closest triangle whose corners all go back within reach instead.
    const Eigen::Vector3d p = P.row(k).transpose();
    double best = std::numeric_limits<double>::infinity();
    int best_face = -1;
    Eigen::Vector3d best_point, best_weights;
    for (const auto& [u, distance] : reached)
      for (int r : g.remesh_vertices[u])
        for (int candidate : g.remesh_faces[r]) {
          if (!on_part(remesh.F, candidate, g.back, reached)) continue;
          Eigen::Vector3d weights;
          const Eigen::Vector3d q =
              closest_point_on_triangle(p, remesh.V.row(remesh.F(candidate, 0)).transpose(),
                                        remesh.V.row(remesh.F(candidate, 1)).transpose(),
                                        remesh.V.row(remesh.F(candidate, 2)).transpose(), &weights);
          const double d = (q - p).norm();
          if (d < best) best = d, best_face = candidate, best_point = q, best_weights = weights;
        }
    if (best_face < 0) {
      ++off_part;
      continue;
    }
    ++relocated;
    out.at.face[k] = best_face;
    out.at.barycentric.row(k) = best_weights.transpose();
    out.at.closest.row(k) = best_point.transpose();
    out.at.distance[k] = best;
  }
  out.relocated = relocated;
  out.off_part = off_part;
  const double diagonal = finite_bbox_diagonal(input.V);
  out.max_distance = out.at.distance.maxCoeff() / diagonal;
  out.mean_distance = out.at.distance.mean() / diagonal;
  return out;
}

std::string carried_summary(const RemeshSamples& carried) {
  return detail::concat(percent(carried.mean_distance, 3), " of the diagonal on average, at most ",
                        percent(carried.max_distance, 3),
                        carried.relocated ? detail::concat(", ", carried.relocated, " relocated to their part") : "",
                        carried.off_part ? detail::concat(", ", carried.off_part, " off their part") : "");
}

}  // namespace cshapes
