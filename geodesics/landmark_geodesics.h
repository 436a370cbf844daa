// Landmark geodesic rows: the distances from L landmark vertices to all n vertices (L × n floats instead of
// the n × n of geodesics/geodesics.h's all_pairs_geodesics), landmarks chosen by farthest-point sampling on the
// geodesics themselves. What landmark MDS (canon/landmark_mds.h) and other methods that need only a few rows
// of the distance matrix (spectral embeddings, Nyström approximations) start from.
//
// Farthest-point sampling (Gonzalez 1985; the landmark choice of de Silva & Tenenbaum 2004): the first
// landmark is the vertex farthest from `first_hint` (by default the vertex nearest the vertices' centroid, so
// the choice starts at an extremity and does not depend on how the vertices are numbered), each next one the
// vertex farthest from all landmarks so far (ties: the vertex with the smallest coordinates, x then y then z:
// the same vertex however they are numbered). Every landmark's row is one single-source solve, and the solve that picks the
// next landmark is the row of the one just chosen, so L landmarks cost L + 1 solves. The L landmarks cover
// the surface with a covering radius (coverage_radius) that is at most twice the best possible (Gonzalez).
//
// Solvers (GeodesicOptions::method): heat (ours) factorises once and solves one source per landmark; fmm
// precomputes its stencils once; graph runs Dijkstra on the edge graph; heat-cgal and exact build their CGAL
// solver per source (slow, for validation). Rows are the single-source results, not symmetrised: row k
// against all_pairs_geodesics's row is within the method's asymmetry (a fraction of an edge; tested).
// Cost: one factorisation (heat) plus L single-source solves, sequential (farthest-point sampling needs each
// row before it picks the next landmark); memory L × n floats plus O(n) per solve.
// Conventions: distances in the mesh's units. The mesh must be connected (a disconnected one is refused,
// naming its component sizes, since its rows would hold infinities) and L ≤ n.
#pragma once

#include <memory>
#include <vector>

#include "cshapes/geodesics/geodesics.h"
#include "cshapes/mesh/mesh.h"

namespace cshapes {

struct LandmarkGeodesicsOptions {
  Index count = 100;          // L, the number of landmarks (clamped to n)
  int first_hint = -1;        // farthest-point sampling starts at the vertex farthest from this one; −1: the
                              // vertex nearest the centroid (central_vertex)
  GeodesicOptions geodesics;  // the single-source solver (heat by default); progress: per landmark

  // Every field by name, for cache keys (support/option_fields.h). Self: LandmarkGeodesicsOptions, const or not.
  template <class Self, class Visit>
  static void for_each_field(Self& o, Visit&& visit) {
    visit("count", o.count);
    visit("first_hint", o.first_hint);
    visit("geodesics", o.geodesics);
  }
};

struct LandmarkGeodesics {
  std::vector<int> landmarks;  // L vertex indices, in the order farthest-point sampling chose them
  Eigen::MatrixXf rows;        // L × n: rows(k, j) = geodesic distance from landmarks[k] to vertex j
  // Largest distance from any vertex to its nearest landmark: how densely the landmarks cover the surface.
  double coverage_radius = 0;
  double seconds = 0;  // wall time
};

// One-shot: landmarks by farthest-point sampling and their rows.
LandmarkGeodesics landmark_geodesics(const Mesh& mesh, const LandmarkGeodesicsOptions& options = {});

class SingleSourceGeodesics;
// The same with a solver already set up (e.g. graph distances on a point cloud's kNN graph) on the points V
// (its vertices: the tie-break and the central vertex); count and first_hint as in LandmarkGeodesicsOptions,
// progress per landmark.
LandmarkGeodesics landmark_geodesics(const SingleSourceGeodesics& solver, const Points& V, Index count,
                                     int first_hint = -1, const ProgressFn& progress = {});

// The choices of farthest-point sampling as functions of the geometry, not of the vertex numbering.
// Whether vertex a comes before vertex b by its coordinates (x, then y, then z).
bool before_by_position(const Points& V, Index a, Index b);
// The index of the largest value (ties: the vertex first by before_by_position).
Index argmax_by_position(const Eigen::VectorXd& value, const Points& V);
// The vertex nearest the centroid of V (ties: before_by_position).
Index central_vertex(const Points& V);

// Rows for given landmark vertices (no sampling): rows(k, j) = d(landmarks[k], j). Throws for an index out of
// range and on a disconnected mesh.
Eigen::MatrixXf geodesic_rows_from(const Mesh& mesh, const std::vector<int>& landmarks,
                                   const GeodesicOptions& options = {});

// A single-source geodesic solver whose set-up (factorisation, stencils, edge graph) is done once for many
// sources: what landmark_geodesics uses, for callers that pick their own sources one at a time.
class SingleSourceGeodesics {
 public:
  SingleSourceGeodesics(const Mesh& mesh, const GeodesicOptions& options = {});
  // Graph distances (Dijkstra) on the edges E between the points V (a point cloud's kNN graph), which must
  // be connected.
  SingleSourceGeodesics(const Points& V, const Edges& E);
  ~SingleSourceGeodesics();
  SingleSourceGeodesics(const SingleSourceGeodesics&) = delete;
  SingleSourceGeodesics& operator=(const SingleSourceGeodesics&) = delete;
  // Distances from `source` to every vertex (n values), checked finite (the mesh is connected). Thread-safe.
  Eigen::VectorXd distances(int source) const;
  Index num_vertices() const;

 private:
  struct Impl;
  std::unique_ptr<Mesh> graph_points_;  // the graph constructor's points (Impl refers to a mesh)
  std::unique_ptr<Impl> impl_;
};

}  // namespace cshapes
