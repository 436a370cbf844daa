// Meshes made here, with known answers, for tests and for data on a machine without any.
#pragma once

#include <cstdint>

#include "core/mesh.h"

namespace cshapes {

// Icosahedron subdivided `subdivisions` times, projected to the sphere of `radius` about the origin.
// 10·4^s + 2 vertices, 20·4^s faces, χ = 2. Faces counter-clockwise seen from outside.
Mesh icosphere(int subdivisions, double radius = 1.0);

// Torus about the z axis: tube centre at distance R from the axis, tube radius r; nu × nv vertices
// (nu around the axis, nv around the tube), 2·nu·nv faces, χ = 0. Area 4π²Rr in the limit.
Mesh torus(int nu, int nv, double R = 1.0, double r = 0.3);

// Flat grid in z = 0 of nx × ny vertices spanning [0, width] × [0, height]; 2(nx-1)(ny-1) faces, χ = 1,
// alternating diagonals so the triangulation has no preferred direction.
Mesh grid(int nx, int ny, double width = 1.0, double height = 1.0);

// The Swiss roll: the rectangle (t, y) ∈ [t0, t1] × [0, height] rolled as x = t cos t, z = t sin t.
// nu samples along the roll (equally spaced in arc length), nv across. nu = 51, nv = 11 gives the paper's
// 561 vertices. Its geodesic length along the roll is swiss_roll_length(t0, t1).
struct SwissRollOptions {
  int nu = 51;                      // vertices along the roll
  int nv = 11;                      // vertices across the roll
  double t0 = 1.5 * 3.14159265358979323846;  // spiral angle where the roll starts (radians)
  double t1 = 4.5 * 3.14159265358979323846;  // spiral angle where it ends: 1.5 turns
  double height = 21.0;             // width across the roll, in the units of x and z
};
Mesh swiss_roll(const SwissRollOptions& options = {});

// n points on a lumpy, elongated closed surface (a sphere radially perturbed by smooth bumps, scaled 3 : 1.5 : 1),
// drawn at random for `seed`: distinct principal axes and no symmetry, so a rigid motion of it is recoverable
// (ICP tests and benchmarks).
Points lumpy_blob(Index n, std::uint64_t seed);

// Arc length of the spiral (t cos t, t sin t) from t0 to t1.
double swiss_roll_length(double t0, double t1);

}  // namespace cshapes
