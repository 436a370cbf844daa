// Geodesic distances on a triangle mesh: single-source, multi-source and all-pairs.
//
// Methods (GeodesicOptions::method):
//   graph  Dijkstra along mesh edges: exact on the edge graph, an upper bound of the surface geodesic
//          (typically 5-10% longer on irregular triangulations). Works on point-cloud kNN graphs too.
// Further methods (fast marching, heat method, exact) are added behind the same interface.
//
// Distances are in the mesh's units. Unreachable vertices (other components) get +infinity.
#pragma once

#include <string>
#include <vector>

#include "core/distance_matrix.h"
#include "core/mesh.h"
#include "core/progress.h"

namespace cshapes {

enum class GeodesicMethod {
  Graph,  // Dijkstra on the edge graph
};

// Parses "graph" (and the other method names as they are added); throws listing the known names otherwise.
GeodesicMethod parse_geodesic_method(const std::string& name);
std::string to_string(GeodesicMethod method);

struct GeodesicOptions {
  GeodesicMethod method = GeodesicMethod::Graph;  // see the table above
  ProgressFn progress;                             // all-pairs only: called as sources finish
};

// Distances from the nearest of `sources` to every vertex (n values).
Eigen::VectorXd geodesic_distances(const Mesh& mesh, const std::vector<int>& sources,
                                   const GeodesicOptions& options = {});

// All n×n distances, symmetrised ((D + Dᵀ)/2), zero diagonal, OpenMP over sources.
// Refuses up front, with the figures, when n² floats do not fit in the available memory.
DistanceMatrix all_pairs_geodesics(const Mesh& mesh, const GeodesicOptions& options = {});

// Dijkstra on an arbitrary weighted edge graph (rest lengths as weights) from several sources.
Eigen::VectorXd dijkstra(Index num_vertices, const Adjacency& adj, const Eigen::VectorXd& edge_weights,
                         const std::vector<int>& sources);

}  // namespace cshapes
