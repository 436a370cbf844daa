// Isosurface extraction by marching tetrahedra: the zero level set of a scalar field sampled on a regular
// grid, each cube split into the 6 tetrahedra of the Kuhn triangulation (around its main diagonal). The split
// is the same in every cube, so neighbouring tetrahedra agree on shared faces and the surface is a closed,
// consistently oriented 2-manifold wherever the field is negative inside the box and positive on its border
// (no lookup tables, no ambiguous cases, unlike marching cubes). Triangles are of poor quality (slivers):
// remesh afterwards. Cost: O(grid points) field evaluations (OpenMP) + O(cells).
#pragma once

#include <functional>

#include "cshapes/mesh/mesh.h"

namespace cshapes {

struct MarchingTetrahedraOptions {
  double cell_size = 1.0;  // grid spacing, in the field's units
  double min_edge_fraction =
      0.05;  // crossing points kept this fraction of a grid edge away from its ends
             // (avoids zero-length edges; moves the surface by at most this × cell_size)
};

// Zero level set of `field` (negative inside) over the box [lo, hi]; faces counter-clockwise seen from
// outside (the side where the field is positive). The field must be positive on the box's border for a closed
// result.
Mesh marching_tetrahedra(const std::function<double(const Eigen::Vector3d&)>& field,
                         const Eigen::Vector3d& lo, const Eigen::Vector3d& hi,
                         const MarchingTetrahedraOptions& options = {});

}  // namespace cshapes
