// Intrinsic Delaunay triangulation (Bobenko & Springborn 2007; Fisher et al. 2006): the same surface and
// vertices, with edges flipped *intrinsically* (new edges are geodesics across two triangles, measured by
// unfolding, never by moving a vertex) until every interior edge is locally Delaunay (the two angles facing
// it sum to at most π). Its cotangent Laplacian has non-negative weights, which is what makes the heat method
// accurate on meshes with obtuse or needle triangles (CGAL's Heat_method_3 "Intrinsic_Delaunay" mode).
//
// An intrinsic triangulation is combinatorial faces plus edge lengths: there are no vertex positions for its
// edges (they cross the original triangles). Faces keep the orientation of the input.
// Edges in one face only (boundary) or in more than two (non-manifold) are never flipped.
// Cost: O(m) setup plus the flips (typically a few percent of the edges on a remeshed scan).
#pragma once

#include "core/mesh.h"

namespace cshapes {

struct IntrinsicTriangulation {
  Faces F;                  // m×3, 0-based vertex indices (an edge may join a vertex to itself after flips)
  Eigen::MatrixX3d length;  // m×3: length(f, k) = length of the edge from F(f, k) to F(f, (k+1) % 3)
  Index flips = 0;          // edge flips performed
};

// The mesh's own triangles with their Euclidean edge lengths.
IntrinsicTriangulation intrinsic_triangulation(const Mesh& mesh);

struct IntrinsicDelaunayOptions {
  double tolerance = 1e-12;  // flip when cot α + cot β < -tolerance (relative: cotangents are dimensionless)
  Index max_flips = 0;  // 0: no limit besides 100 × the number of edges (a guard; termination is proven)
};

// Flips the mesh's edges to the intrinsic Delaunay triangulation.
IntrinsicTriangulation intrinsic_delaunay(const Mesh& mesh, const IntrinsicDelaunayOptions& options = {});

// Interior manifold edges whose facing angles sum to more than π (cot α + cot β < -tolerance).
Index non_delaunay_edges(const IntrinsicTriangulation& T, double tolerance = 1e-9);

// Area of face f from its edge lengths (Heron's formula, in its stable ordering).
double intrinsic_face_area(const IntrinsicTriangulation& T, Index f);

}  // namespace cshapes
