// Meshes made here, with known answers, for tests and for data on a machine without any.
#pragma once

#include <cstdint>
#include <random>
#include <string>
#include <utility>

#include "cshapes/support/distance_matrix.h"
#include "cshapes/mesh/mesh.h"

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
  int nu = 51;                               // vertices along the roll
  int nv = 11;                               // vertices across the roll
  double t0 = 1.5 * 3.14159265358979323846;  // spiral angle where the roll starts (radians)
  double t1 = 4.5 * 3.14159265358979323846;  // spiral angle where it ends: 1.5 turns
  double height = 21.0;                      // width across the roll, in the units of x and z
};
Mesh swiss_roll(const SwissRollOptions& options = {});
// The grid nu × nv closest to n vertices with the paper's aspect (nu − 1) : (nv − 1) = 5 : 1 (561: 51 × 11),
// as `cshapes generate swissroll --vertices n` uses it. n ≥ 4.
std::pair<int, int> swiss_roll_grid(long n);

// n points on a lumpy, elongated closed surface (a sphere radially perturbed by smooth bumps, scaled 3 : 1.5
// : 1), drawn at random for `seed`: distinct principal axes and no symmetry, so a rigid motion of it is
// recoverable (ICP tests and benchmarks).
Points lumpy_blob(Index n, std::uint64_t seed);

// A closed capsule (genus 0): a cylinder of `radius` whose axis runs `length` along x (from 0 to length),
// capped by two hemispheres, so the surface is length + 2·radius long end to end and its geodesic distance
// along the axis is length + π·radius pole to pole. `segments` vertices around every ring; rings are spaced
// about one edge length 2π·radius/segments apart along the cylinder and the caps (the last cap ring's
// triangles near the poles are needles, the poles have valence `segments`). With bend ≠ 0 the axis is bent
// into a circular arc of total angle `bend` (radians) in the x-y plane (keeping its length): a long
// articulated-looking body. Faces counter-clockwise seen from outside.
struct CapsuleOptions {
  double length = 10.0;  // length of the cylindrical part, along the axis
  double radius = 1.0;   // radius of the cylinder and of the hemispherical caps
  int segments = 12;     // vertices around each ring (>= 3)
  double bend = 0.0;     // total bend angle of the axis (radians); 0: straight, along x
};
Mesh capsule(const CapsuleOptions& options = {});

// Splits every `every`-th face (f = 0, every, 2·every, ...) into three at the point of barycentric
// coordinates (w0, w1, 1 - w0 - w1): each split adds one vertex of valence 3 and, for weights far from 1/3,
// needle and obtuse triangles. The surface itself is unchanged (the new vertex lies in the face's plane).
Mesh split_faces(const Mesh& mesh, int every, double w0 = 0.6, double w1 = 0.3);

// Arc length of the spiral (t cos t, t sin t) from t0 to t1.
double swiss_roll_length(double t0, double t1);

// n points drawn uniformly by area on the Swiss roll of `options` (nu, nv unused), for `seed` (std::mt19937),
// with their geodesic distances known exactly: the roll is developable, so the geodesic distance of two
// points is the Euclidean distance of their (arc length, height) coordinates in the unrolled rectangle.
// The 3-D position takes the spiral angle from a 4,096-entry table of arc length: the middle of the table
// cell AFTER the one holding the point's arc length (as cshapes bench smacof has always drawn its start), so
// X lies 0.5 to 1.5 cells (of 1/4,096 of the angle span) further along the roll than `flat` says; `flat` and
// the distances are exact. X serves as a starting configuration, not as ground truth.
struct SwissRollSample {
  Points X;               // n×3 points on the roll
  Eigen::MatrixX2d flat;  // n×2 (arc length from t0, height): the same points unrolled
};
SwissRollSample random_swiss_roll_points(Index n, unsigned seed, const SwissRollOptions& options = {});

// The n×n geodesic distances of a SwissRollSample (Euclidean distances of its `flat` rows), in single
// precision. Throws cshapes::Error (before allocating) when the matrix does not fit in the memory available.
// OpenMP over columns.
DistanceMatrix swiss_roll_geodesic_distances(const SwissRollSample& sample);

// Random point sets for the Coulomb benchmarks and tests:
//   Uniform    in the unit cube [0, 1]³
//   Sphere     on the unit sphere (normalised Gaussian vectors)
//   Clustered  20 Gaussian clusters, centres uniform in the unit cube, widths log-uniform in 1e-3 … 1e-1,
//              populations drawn with weights uniform in [1, 10] (the hard case for a tree's adaptivity)
enum class PointDistribution { Uniform, Sphere, Clustered };
// "uniform", "sphere", "clustered"; throws cshapes::Error naming the known ones otherwise.
PointDistribution parse_point_distribution(const std::string& name);
std::string to_string(PointDistribution distribution);  // the name parse_point_distribution takes
// n points of the distribution, drawn from rng (which advances; the same rng state gives the same points).
Points random_points(Index n, PointDistribution distribution, std::mt19937_64& rng);

// n points uniformly distributed by area on the mesh's triangles (a triangle by area, then a uniform point in
// it), drawn from rng. The mesh needs at least one face of positive area.
Points sample_surface(const Mesh& mesh, Index n, std::mt19937_64& rng);

}  // namespace cshapes
