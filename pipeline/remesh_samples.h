// Vertices of an input mesh carried to its remesh (pipeline/resampled_dataset.h), for the measurements whose
// ground truth names the input's vertices (experiments/pose_invariance.h with --resample): each vertex goes
// to the closest point of the remeshed surface, as a face and barycentric coordinates
// (core/locate_on_surface.h), where anything computed per vertex of the remesh (a canonical form) is then
// interpolated (interpolate_on_surface).
//
// How far the vertices moved is measured (the distances to the located points, over the input's
// bounding-box diagonal; at most the remesh's Hausdorff distance), and so is the one way the closest point
// can be the wrong one: where two parts of the surface almost touch (an arm lying against the body) closer
// than the remesh's sag, the closest remeshed triangle may belong to the other part. A located point is
// counted "off its part" when a corner of its triangle, taken back to the input (its nearest input vertex),
// is not within reach of the vertex along the input's edges: a graph distance of 2 × (the distance to the
// located point + the triangle's longest edge) + the input's longest edge at the vertex (Dijkstra, bounded).
// At a tip the remesh cuts off (toes, fingertips, the nose), the triangle's corners lie on the same part,
// a few remesh edges along the surface: they are reached, where the other side of a gap is not.
//
// Cost: an AABB tree on the remesh and a kd-tree on the input, O(n log n); per vertex a closest-point query
// and a bounded Dijkstra over the input vertices within a few remesh edges.
#pragma once

#include <vector>

#include "core/locate_on_surface.h"
#include "core/mesh.h"

namespace cshapes {

struct RemeshSamples {
  std::vector<int> vertices;  // input vertex indices, as given
  SurfaceLocations at;        // where each lies on the remesh (rows in the order of `vertices`)
  double mean_distance = 0;   // mean ‖vertex − located point‖ / the input's bounding-box diagonal
  double max_distance = 0;    // the largest, likewise
  int off_part = 0;           // located on a triangle of another part of the surface (see above)
};

// Carries `vertices` of `input` to `remesh` (a remesh of the same surface, faces of positive area). Throws
// cshapes::Error for a vertex index out of range or a remesh without faces.
RemeshSamples carry_to_remesh(const Mesh& input, const Mesh& remesh, const std::vector<int>& vertices);

}  // namespace cshapes
