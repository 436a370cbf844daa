// Mesh refinement that keeps the surface: 1-to-4 midpoint subdivision and longest-edge bisection, and the
// two combined to reach an exact vertex count (benchmarks at a prescribed size from a smaller mesh).
// Every new vertex is an edge midpoint, so the refined mesh lies on the input surface (piecewise-linear),
// the input's vertices keep their indices (rows 0 .. n−1 come first), and the topology (Euler
// characteristic, components, boundary loops) is unchanged. Face orientation is kept.
#pragma once

#include "cshapes/mesh/mesh.h"

namespace cshapes {

// Every triangle into four: the edge midpoints become vertices n .. n+|E|−1, in the order of mesh_edges(F).
// V + E vertices, 4F faces. O(F log F).
Mesh midpoint_subdivide(const Mesh& mesh);

// Splits the longest edges at their midpoints (each split adds one vertex and turns the edge's one or two
// triangles into two each) until the mesh has exactly `target` vertices. Works in rounds: a round splits the
// edges by decreasing length, skipping an edge that shares a triangle with one already split in the round.
// Edges of more than two triangles (non-manifold) are never split. Throws cshapes::Error when no edge can be
// split. A target at or below the vertex count returns the mesh unchanged.
Mesh split_longest_edges(Mesh mesh, Index target);

struct RefineToVertexCountResult {
  Mesh mesh;              // exactly `target` vertices
  int subdivisions = 0;   // 1-to-4 midpoint subdivisions applied first
  Index edge_splits = 0;  // longest-edge splits applied after them
};

// Midpoint subdivisions while the next one does not overshoot `target`, then longest-edge splits up to it.
RefineToVertexCountResult refine_to_vertex_count(Mesh mesh, Index target);

}  // namespace cshapes
