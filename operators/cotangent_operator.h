// The cotangent operators of a triangle mesh, written once: the cotangent of a triangle's angle from its
// three side lengths, the cotangent stiffness matrix and the lumped (barycentric) mass of an intrinsic
// triangulation, and the lumped mass of a mesh from its coordinates. The heat method (geodesics/heat_method.h),
// the Laplace–Beltrami eigensolver (operators/laplace_beltrami.h), the intrinsic Delaunay flips
// (operators/intrinsic_delaunay.h) and SMACOF's area weights (canon/smacof.h) all take them from here, as
// geometry-central's IntrinsicGeometryInterface or libigl's cotmatrix/massmatrix serve their libraries.
//
// Conventions (the positive semi-definite sign, as in the heat method's paper):
//   L_ab = −½ (cot α_ab + cot β_ab) for an edge ab with opposite angles α, β (one of them on a boundary),
//   L_aa = −Σ_b L_ab, so L·1 = 0;  M_aa = ⅓ Σ_{faces at a} area.
// For any function u, uᵀLu = Σ_f area_f |∇u|² over the piecewise linear interpolant: on a flat mesh L is zero
// on linear functions at every interior vertex; on a unit sphere the coordinate functions satisfy L x ≈ 2 M x.
#pragma once

#include <Eigen/Core>
#include <Eigen/SparseCore>

#include "cshapes/operators/intrinsic_delaunay.h"
#include "cshapes/mesh/mesh.h"

namespace cshapes {

// Heron's formula with the sides sorted (Kahan's stable form): the area of the triangle with side lengths a,
// b, c, in any order; 0 for a degenerate or impossible triangle.
double heron_area(double a, double b, double c);

// The cotangent of the angle facing the side of length `opposite` in the triangle whose other two sides are
// x and y: (x² + y² − opposite²) / (4 · area), the area by heron_area (floored at 1e-300).
double cotangent(double opposite, double x, double y);

struct CotangentOperator {
  Eigen::SparseMatrix<double> L;  // n×n cotangent stiffness: symmetric, L·1 = 0
  Eigen::VectorXd mass;           // n lumped masses; 0 for a vertex in no face
};

// The cotangent stiffness and lumped mass of the triangles of T (edge lengths only) over num_vertices
// vertices. Face areas by heron_area.
CotangentOperator cotangent_operator(const IntrinsicTriangulation& T, Index num_vertices);

// The lumped (barycentric) mass of a mesh from its vertex coordinates: a third of the area of every face at
// the vertex (area from the cross product); 0 for a vertex in no face.
Eigen::VectorXd lumped_mass(const Mesh& mesh);

}  // namespace cshapes
