// Remeshing a triangle mesh to a prescribed number of vertices, and the measures that say whether the shape
// and the triangle quality survived (Hausdorff distance, angles). The implementation (remesh_cgal.cpp) uses
// CGAL's isotropic remeshing and Lindstrom-Turk edge-collapse simplification; this header shows only Eigen
// types.
//
// Shape: a first run without constraints gives the best triangles; when its Hausdorff distance to the input
// exceeds max_hausdorff_fraction × the bbox diagonal (thin fins, sharp tips), further runs keep the sharp
// edges (dihedral angle > feature_angle_deg, then 0.75 and 0.5 times that) as polylines, until one meets the
// goal; otherwise the closest is returned. Badly shaped triangles are finally improved by edge flips where
// the surface is flat (and caps flipped anywhere), which moves no vertex. How the count is hit: isotropic
// remeshing of the input with a target edge length L gives roughly 2A / (√3 L²) vertices (A: area;
// equilateral triangles, F ≈ 2V). L is adjusted from the count obtained (N ∝ 1/L²) until the remeshed surface
// has a few more vertices than asked, then edges are collapsed (cheapest first) down to exactly the target,
// and one pass of tangential relaxation restores the angles. Every attempt starts again from the input, so
// the shape is always projected onto the original surface. Topology is kept: a closed mesh stays closed, the
// Euler characteristic and the number of components do not change. Cost: O(n log n) per attempt (AABB tree
// projection), a few attempts.
#pragma once

#include "cshapes/mesh/mesh.h"
#include "cshapes/support/progress.h"

namespace cshapes {

struct RemeshOptions {
  Index target_vertices = 0;  // vertices wanted (required, >= 4)
  double tolerance =
      0.01;  // accepted relative deviation |n - target| / target (the exact target is aimed at)
  int relaxation_iterations =
      3;                 // isotropic remeshing iterations (split, collapse, flip, relax, project) per attempt
  int max_attempts = 8;  // edge-length adjustments before giving up
  bool protect_border =
      false;  // true: border edges are neither split nor collapsed (the border polyline is kept)
  double feature_angle_deg =
      60;  // fallback: edges whose dihedral angle exceeds this stay on their polyline; 0: none
  double max_hausdorff_fraction =
      0.01;  // Hausdorff goal (× bbox diagonal) that triggers the feature-line fallback
  double presimplify_factor =
      6;  // input with more than this × target vertices: collapse to half of that first; 0: never
  // Called after every attempt (stage "remesh") and polled (an empty stage) within one. done / total counts
  // attempts over every run the remesh may make (the plain one, then feature-line ones), so it jumps ahead
  // when a run meets the goal, and reaches total only as remesh() returns.
  ProgressFn progress;
};

struct RemeshResult {
  Mesh mesh;                      // the remeshed surface (new vertices, new faces)
  double target_edge_length = 0;  // L of the last isotropic remeshing attempt, in mesh units
  int attempts = 0;               // isotropic remeshing runs made (all feature-line variants together)
  Index remeshed_vertices = 0;    // vertex count after the last isotropic remeshing, before collapsing
  Index collapsed_edges = 0;      // edges collapsed to reach the target
  double hausdorff = -1;          // Hausdorff distance to the input when measured (-1: not measured)
  bool feature_lines = false;     // whether sharp edges were kept as constraints (the fallback)
  double feature_angle_deg = 0;   // the dihedral-angle threshold of those feature lines
};

// Remeshes `mesh` (a valid triangle mesh, manifold; boundaries allowed) to target_vertices within the
// tolerance. Throws cshapes::Error when an option is out of range, when remesh_memory_bytes(target) exceeds
// the memory available (before any work), when the input is not a manifold triangle mesh or the count cannot
// be reached.
RemeshResult remesh(const Mesh& mesh, const RemeshOptions& options);

// The memory remesh() needs for a target vertex count (bytes, an upper estimate measured on CGAL's
// structures).
double remesh_memory_bytes(Index target_vertices);

// Symmetric Hausdorff distance between two surfaces, approximated by sampling: every vertex, edge midpoint
// and face centroid of each mesh is projected onto the other (exact point-to-triangle distances via an AABB
// tree: mesh/locate_on_surface.h, so any triangle mesh, non-manifold too; faces of zero area are left out of
// the target). Units of the meshes. A lower bound of the true Hausdorff distance, tight to within about half
// an edge's sag.
double hausdorff_distance(const Mesh& a, const Mesh& b);

// Triangle angles in degrees: the smallest one in the mesh, and the mean over faces of each face's smallest
// angle.
struct AngleStats {
  double min_angle = 0;
  double mean_min_angle = 0;
  double max_angle = 0;
};
AngleStats angle_stats(const Mesh& mesh);

// True when two faces of the mesh intersect other than along shared vertices or edges (CGAL's exact test).
bool self_intersects(const Mesh& mesh);

}  // namespace cshapes
