// A triangle mesh (or, with no faces, a point cloud) and its combinatorial and metric summaries.
#pragma once

#include <string>
#include <vector>

#include "cshapes/support/types.h"

namespace cshapes {

// V: n×3 vertex positions. F: m×3 triangles (0-based); F has zero rows for a point cloud.
struct Mesh {
  Points V;
  Faces F;

  Index num_vertices() const { return V.rows(); }
  Index num_faces() const { return F.rows(); }
  bool is_point_cloud() const { return F.rows() == 0; }
};

// A mesh from a vertex list and a triangle list (0-based indices into the vertices), as the generators build
// them; no validation.
Mesh mesh_from_vectors(const std::vector<Eigen::Vector3d>& vertices,
                       const std::vector<Eigen::Vector3i>& triangles);

// Unique undirected edges of the triangles, each (i, j) with i < j, sorted lexicographically.
Edges mesh_edges(const Faces& F);

// Euclidean length of each edge in V: the rest lengths d_ij of the paper.
Eigen::VectorXd edge_lengths(const Points& V, const Edges& E);

// Compressed sparse row adjacency of an undirected graph on n vertices:
// the neighbours of vertex i are neighbors[offsets[i] .. offsets[i+1]), and edge_ids gives, for each of
// those, the row of E it came from. Neighbours are sorted by index.
struct Adjacency {
  std::vector<int> offsets;    // n+1
  std::vector<int> neighbors;  // 2|E|
  std::vector<int> edge_ids;   // 2|E|
  int degree(Index i) const { return offsets[i + 1] - offsets[i]; }
};
Adjacency adjacency(Index num_vertices, const Edges& E);

// Connected components of the graph (isolated vertices are components of their own).
// label[i] in [0, count); components are numbered by their smallest vertex.
struct Components {
  int count = 0;
  std::vector<int> label;
  std::vector<int> sizes;
  int largest() const;  // label of the component with most vertices (first on a tie)
};
Components connected_components(Index num_vertices, const Edges& E);

// Union-find: the root of i's set in `parent` (parent[r] == r at a root), halving the path on the way.
int union_find_root(std::vector<int>& parent, int i);

// For each edge of mesh_edges(F), how many triangles contain it (1: boundary, 2: interior, >2: non-manifold).
std::vector<int> edge_face_counts(const Faces& F, const Edges& E);

// Combinatorial and metric summary, as `cshapes info` prints it.
struct MeshInfo {
  Index vertices = 0;
  Index faces = 0;
  Index edges = 0;
  int components = 0;
  Index isolated_vertices = 0;    // vertices in no face (each is a component of its own)
  Index boundary_edges = 0;       // edges in exactly one face
  int boundary_loops = 0;         // closed chains of boundary edges
  Index nonmanifold_edges = 0;    // edges in more than two distinct faces (mesh/mesh_defects.h)
  long euler_characteristic = 0;  // V - E + F
  // Total genus: sum over components of (2 - chi_c - b_c) / 2, assuming orientable surfaces.
  // -1 when it is undefined (point cloud, non-manifold edges or vertices, duplicate or repeated-vertex
  // faces).
  long genus = 0;
  double bbox_diagonal = 0;
  double mean_edge_length = 0;
  double area = 0;
};
MeshInfo mesh_info(const Mesh& mesh);

// Total surface area of the triangles.
double surface_area(const Points& V, const Faces& F);
// The resolution of a triangulation as seen by an iteration that steps by its mean edge h̄: the vertex count
// of an even (equilateral) triangulation with the same area A and the same mean edge, A / (√3/2 · h̄²), h̄ over
// the distinct edges. About the vertex count for an isotropic remesh; an uneven scan triangulation (long
// edges on flat parts, short ones at features) of 12,000 vertices comes out at 8,000–9,000. 0 when the area
// or the mean edge is 0.
double even_triangulation_vertices(const Points& V, const Faces& F);
// Area-weighted vertex normals (unit length; zero for isolated vertices and where the faces' normals cancel).
Points vertex_normals(const Mesh& mesh);
// Length of the diagonal of the axis-aligned bounding box.
double bbox_diagonal(const Points& V);
// The same over the rows with finite coordinates only (a canonical form marks the vertices a repair dropped with
// NaN rows); 0 when there is none.
double finite_bbox_diagonal(const Points& V);

// The sub-mesh made of one connected component (vertices renumbered in their original order).
// vertex_map[k] is the original index of new vertex k.
struct Submesh {
  Mesh mesh;
  std::vector<int> vertex_map;
};
Submesh extract_component(const Mesh& mesh, const Components& components, int label);

// Requires one connected component; otherwise throws with the sizes found, and says how to proceed.
// With keep_largest, returns the largest component and writes what was dropped into *note.
Submesh require_connected(const Mesh& mesh, const std::string& name, bool keep_largest, std::string* note);

}  // namespace cshapes
