// Shared type aliases. Every geometric array in cshapes is a plain Eigen matrix, one row per element.
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>

namespace cshapes {

using Eigen::Index;
// n×3 vertex positions, one row a vertex (units: those of the input file).
using Points = Eigen::MatrixX3d;
// m×3 triangle vertex indices, 0-based, counter-clockwise seen from outside.
using Faces = Eigen::MatrixX3i;
// |E|×2 undirected edges, 0-based, each row (i, j) with i < j.
using Edges = Eigen::MatrixX2i;

}  // namespace cshapes
