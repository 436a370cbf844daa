// Repairs a mesh for what a method needs, and says what it did.
//
// Readers accept imperfect meshes (mesh/io.h) and mesh/mesh_defects.h describes them; each method states its
// requirements here and repair_for changes only what those requirements forbid:
//
//   edge_graph()        Coulomb canonization (§2 needs only the edge graph and its lengths): faces repeating
//                       a vertex and duplicate faces dropped, isolated vertices dropped, the largest
//                       connected component kept. Non-manifold edges and vertices are fine.
//   manifold_surface()  geodesics behind MDS (heat method, fast marching: cotangent Laplacian, unfoldings)
//                       and MDS itself (one component): the above, plus zero-area faces dropped and
//                       non-manifold vertices split, then the largest component kept.
//
// Non-manifold vertices (and the endpoints of non-manifold edges) are SPLIT: each fan of faces around the
// vertex (faces joined across edges of exactly two faces) gets its own copy of the vertex, same position.
// Splitting rather than dropping the offending faces keeps every face, the surface area and the vertex
// positions; a geodesic can no longer pass through the pinch from one sheet to the other, which is what a
// surface touching itself at a point or along an edge should not allow anyway (it is the topological noise
// the paper is about). After the split every edge has at most two faces (a fan holds at most two faces of
// an edge at each end) and every vertex one fan. Dropping faces instead would open holes next to the
// pinch and lose area. Zero-area faces are dropped (they have no area to lose; their cotangents are
// infinite).
//
// The result's vertices are a subset of the input's, in input order, followed by the copies made by
// splitting; vertex_map[k] is the input vertex of repaired vertex k (a split vertex appears several times).
// Point clouds (no faces) are returned unchanged: their graph is the method's (kNN) business.
#pragma once

#include <string>
#include <vector>

#include "cshapes/support/distance_matrix.h"
#include "cshapes/mesh/mesh.h"
#include "cshapes/support/progress.h"

namespace cshapes {

struct MeshRequirements {
  bool single_component = true;      // keep the largest connected component
  bool manifold = false;             // split non-manifold vertices (and non-manifold edges' endpoints)
  bool no_degenerate_faces = false;  // drop zero-area faces
  Index min_vertices = 4;            // fewer left after repair: refused (a canonical form in 3-D needs 4)

  static MeshRequirements edge_graph();        // Coulomb
  static MeshRequirements manifold_surface();  // heat method, fast marching, MDS
};

// One kind of change: what, and how many elements it concerned.
struct RepairAction {
  std::string what;  // e.g. "duplicate faces dropped"
  Index count = 0;
};

struct RepairedMesh {
  Mesh mesh;
  std::vector<int> vertex_map;  // repaired vertex k -> input vertex (see above)
  Index input_vertices = 0;
  std::vector<RepairAction> actions;  // empty: the mesh needed nothing (mesh equals the input)
  // One line: "NAME: repaired for PURPOSE: duplicate faces dropped 1, ...", or "" when nothing was done.
  std::string text;
  bool changed() const { return !actions.empty(); }
};

struct RepairOptions {
  bool strict = false;        // refuse (throw, naming the defects) instead of repairing
  std::string name = "mesh";  // starts every message (the file's path)
  std::string purpose;        // "the heat method", ...: what the requirements are for, in messages
  ProgressFn progress;        // polled between the passes (support/progress.h: a stop throws from it)
};

// Throws cshapes::Error when strict and a repair is needed, or when fewer than min_vertices remain.
RepairedMesh repair_for(const Mesh& mesh, const MeshRequirements& requirements,
                        const RepairOptions& options = {});

// Per-vertex rows of a result on the repaired mesh, placed back at the input's vertices: input_vertices
// rows, NaN where no repaired vertex maps (dropped), the first copy's row where a vertex was split.
Points to_input_vertices(const Points& X, const std::vector<int>& vertex_map, Index input_vertices);
// The same for one value per vertex; `fill` where dropped.
Eigen::VectorXd to_input_vertices(const Eigen::VectorXd& values, const std::vector<int>& vertex_map,
                                  Index input_vertices, double fill);
// 1 for input vertices that some repaired vertex maps to, 0 for dropped ones.
Eigen::VectorXd valid_input_vertices(const std::vector<int>& vertex_map, Index input_vertices);

// The repaired vertices that stand for input vertex v: none when it was dropped, several when it was split.
std::vector<int> repaired_copies(const std::vector<int>& vertex_map, int v);
// Distances on the repaired mesh placed back at the input's vertices. A split vertex's copies share one
// position, so its distance is the smallest over its copies; a dropped vertex gets NaN (row and column).
Eigen::VectorXd distances_to_input_vertices(const Eigen::VectorXd& d, const std::vector<int>& vertex_map,
                                            Index input_vertices);
DistanceMatrix distances_to_input_vertices(const DistanceMatrix& D, const std::vector<int>& vertex_map,
                                           Index input_vertices);

}  // namespace cshapes
