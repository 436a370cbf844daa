// What is imperfect about a mesh, described exactly: counts and the first few examples of each kind.
//
// The readers (mesh/io.h) accept anything a mesh file can legally hold; this says what was read, and
// mesh/mesh_repair.h repairs what a method needs. Definitions (all indices 0-based):
//   repeated-vertex faces  a face naming one vertex twice or three times (i i j)
//   duplicate faces        a face with the same vertex set as an earlier face (any order or orientation);
//                          counted once per extra copy. A duplicate is not counted again as making its
//                          edges non-manifold.
//   zero-area faces        three distinct vertices, twice the area ‖(b−a)×(c−a)‖ ≤ 1e-12 ·
//   (|ab|²+|bc|²+|ca|²):
//                          collinear or coincident corners
//   zero-length edges      an edge whose endpoints have identical coordinates
//   non-manifold edges     an edge of more than two distinct faces (duplicates and repeated-vertex faces
//                          left out); examples carry how many faces share it
//   non-manifold vertices  a vertex where several sheets of surface meet at one point: its faces form more
//                          than one fan (faces joined across edges of exactly two faces) although it is on no
//                          non-manifold edge (the endpoints of those are split the same way by the repair)
//   isolated vertices      vertices in no face (each is a component of its own)
//   components             connected components of the edge graph, sizes in descending order
//   boundary edges / loops edges of exactly one face, and the connected chains they form
// A point cloud (no faces) has no face or edge defects; its vertices are not counted as isolated.
// Cost: O(m log m) for m faces.
#pragma once

#include <array>
#include <string>
#include <vector>

#include "cshapes/mesh/mesh.h"

namespace cshapes {

struct MeshDefects {
  static constexpr size_t max_examples = 5;  // examples kept per kind

  Index repeated_vertex_faces = 0;
  std::vector<int> repeated_vertex_face_examples;  // face indices
  Index duplicate_faces = 0;
  std::vector<std::array<int, 2>> duplicate_face_examples;  // (face, the earlier face it repeats)
  Index zero_area_faces = 0;
  std::vector<int> zero_area_face_examples;
  Index zero_length_edges = 0;
  std::vector<std::array<int, 2>> zero_length_edge_examples;  // (i, j), i < j
  Index nonmanifold_edges = 0;
  std::vector<std::array<int, 3>> nonmanifold_edge_examples;  // (i, j, faces sharing the edge)
  Index nonmanifold_vertices = 0;
  std::vector<int> nonmanifold_vertex_examples;
  Index isolated_vertices = 0;
  std::vector<int> isolated_vertex_examples;
  int components = 0;
  std::vector<int> component_sizes;  // vertices per component, descending
  Index boundary_edges = 0;
  int boundary_loops = 0;

  // Anything a method may have to repair: any count above except boundaries, or more than one component.
  bool any() const;
  // One line: "1 non-manifold edge (8425-10765, 4 faces); 2 components (9990, 1 vertices)", or "none".
  // Boundaries are described, not listed as defects.
  std::string summary() const;
};

MeshDefects mesh_defects(const Mesh& mesh);

// The repeated-vertex test, the zero-area test and the sorted vertex set, shared with mesh/mesh_repair.cpp.
bool face_repeats_vertex(const Faces& F, Index f);
bool face_has_zero_area(const Points& V, const Faces& F, Index f);
std::array<int, 3> sorted_face(const Faces& F, Index f);

// Fans at every vertex of a face list without repeated-vertex or duplicate faces: the corners (f, c) around
// a vertex joined across edges of exactly two faces. corner_fan[3f + c] numbers the fan of corner c of face f
// at its vertex (0, 1, ... per vertex); fan_count[v] is how many fans vertex v has (0 when in no face).
struct CornerFans {
  std::vector<int> corner_fan;
  std::vector<int> fan_count;
};
CornerFans corner_fans(Index num_vertices, const Faces& F);

// Edges of F (as mesh_edges) with how many faces hold each, over the given faces only.
struct EdgeFaceCount {
  Edges E;
  std::vector<int> faces;
};
EdgeFaceCount edge_face_count(const Faces& F);

}  // namespace cshapes
