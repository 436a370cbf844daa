// Intrinsic Delaunay triangulation (Bobenko & Springborn 2007; Fisher et al. 2006): the same surface and
// vertices, with edges flipped *intrinsically* (new edges are geodesics across two triangles, measured by
// unfolding, never by moving a vertex) until every interior edge is locally Delaunay (the two angles facing
// it sum to at most π). Its cotangent Laplacian has non-negative weights, which is what makes the heat method
// accurate on meshes with obtuse or needle triangles (CGAL's Heat_method_3 "Intrinsic_Delaunay" mode).
//
// An intrinsic triangulation is combinatorial faces plus edge lengths: there are no vertex positions for its
// edges (they cross the original triangles). Faces keep the orientation of the input. After flips a face may
// list a vertex twice, two faces may share two or three edges, and an edge may join a vertex to itself (a
// vertex of degree 1 inside a self-folded triangle): all of these are valid intrinsic triangulations, and the
// flip keeps its half-edge pairing right in them (the twin of each half-edge is carried by identity, not
// looked up by vertex pair).
//
// Robustness, by construction rather than by case (as Sharp & Crane, "A Laplacian for nonmanifold triangle
// meshes", 2020, §4.5):
//   * Mollification: every edge is lengthened by the same δ ≥ 0, the least that makes every triangle satisfy
//     its triangle inequalities by a margin ε = mollify_factor · mean edge length. So no triangle of the input
//     is degenerate (zero-length edges, collinear corners: area ≥ ε²·√3/4) and no length is taken through
//     Heron's formula at the edge of the inequality. δ = 0 on a mesh that has no nearly degenerate triangle;
//     otherwise every distance grows by at most about δ per edge crossed (1e-6 of an edge by default).
//   * Flips keep the margin: an edge is flipped only when the unfolded quadrilateral is strictly convex and
//     both new triangles satisfy their inequalities by ε/2; otherwise it stays (counted in skipped_flips: its
//     cotangent weight may be negative, as on the input mesh, but nothing degenerates). So every triangle of
//     the result has a positive area bounded away from zero, whatever the input.
//   * Edges in one face only (boundary), in more than two (non-manifold), or in two faces of opposite
//     orientation (a non-orientable or inconsistently oriented surface) are never flipped.
// Cost: O(m) setup plus the flips (typically a few percent of the edges on a remeshed scan).
#pragma once

#include <string>
#include <vector>

#include "cshapes/mesh/mesh.h"

namespace cshapes {

struct IntrinsicTriangulation {
  Faces F;                  // m×3, 0-based vertex indices (a face may list a vertex twice after flips)
  Eigen::MatrixX3d length;  // m×3: length(f, k) = length of the edge from F(f, k) to F(f, (k+1) % 3)
  Index flips = 0;          // edge flips performed
  Index skipped_flips = 0;  // non-Delaunay edges left as they were: their flip would be degenerate
  double mollification = 0;  // δ: the length added to every edge of the input (0: none was needed)
  double margin = 0;         // ε: every triangle's a + b - c is at least this (ε/2 for flipped ones)
  std::vector<int> twin;     // 3m: the half-edge 3f+k's twin (3g+j), -1 on boundary or unflippable edges
};

// Relative margin of the mollification: ε = kMollifyFactor · mean edge length (Sharp & Crane's default).
constexpr double kMollifyFactor = 1e-6;

// The mesh's own triangles with their Euclidean edge lengths, mollified (see above; mollify_factor = 0
// keeps the lengths exactly, degenerate triangles included). Throws on a face index outside the vertices.
IntrinsicTriangulation intrinsic_triangulation(const Mesh& mesh, double mollify_factor = kMollifyFactor);

struct IntrinsicDelaunayOptions {
  double tolerance = 1e-12;  // flip when cot α + cot β < -tolerance (relative: cotangents are dimensionless)
  Index max_flips = 0;  // 0: no limit besides 100 × the number of edges (a guard; termination is proven)
  double mollify_factor = kMollifyFactor;  // ε relative to the mean edge length (see above)
};

// Flips the mesh's edges to the intrinsic Delaunay triangulation.
IntrinsicTriangulation intrinsic_delaunay(const Mesh& mesh, const IntrinsicDelaunayOptions& options = {});

// Interior manifold edges whose facing angles sum to more than π (cot α + cot β < -tolerance).
Index non_delaunay_edges(const IntrinsicTriangulation& T, double tolerance = 1e-9);

// Area of face f from its edge lengths (Heron's formula, in its stable ordering).
double intrinsic_face_area(const IntrinsicTriangulation& T, Index f);

// min over the three sides of (sum of the other two − this side): how far face f is from degenerate
// (negative: the lengths are no triangle).
double triangle_inequality_margin(const IntrinsicTriangulation& T, Index f);

// What is wrong with T as an intrinsic triangulation of `mesh`, "" when nothing: twins not mutual or not
// opposite, a face with a non-positive or non-finite margin, a vertex of a face of `mesh` in no face of T.
// For tests and stress runs; O(m).
std::string intrinsic_triangulation_defect(const Mesh& mesh, const IntrinsicTriangulation& T);

}  // namespace cshapes
