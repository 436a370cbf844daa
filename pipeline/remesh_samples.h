// Vertices of an input mesh carried to its remesh (pipeline/resampled_dataset.h), for the measurements whose
// ground truth names the input's vertices (experiments/pose_invariance.h with --resample): each vertex goes
// to the closest point of the remeshed surface, as a face and barycentric coordinates
// (mesh/locate_on_surface.h), where anything computed per vertex of the remesh (a canonical form) is then
// interpolated (interpolate_on_surface).
//
// How far the vertices moved is measured (the distances to the located points, over the input's
// bounding-box diagonal; at most the remesh's Hausdorff distance where no vertex is relocated, see below).
// The closest point can be on the wrong part of the surface: where two parts almost touch (an arm lying
// against the body) closer than the remesh's sag, the closest remeshed triangle may be the other part's.
// A located triangle is on the sample's part when each of its corners, taken back to the input (its nearest
// input vertex), lies within reach of the sample along the input's edges (Dijkstra, bounded at 10 mean
// remesh edges + twice the sample's distance to the triangle + twice its longest input edge: folds narrower
// than that, lips or eyelids, are below the remesh's resolution). A sample closest to another part is
// located instead on the closest triangle whose corners all lie within that reach ("relocated"); one with
// no such triangle keeps its closest point and is counted "off its part". KIDS at 5,000 vertices (remesh
// edge 1.3, bounding-box diagonal ~140): 3, 33 and 61 of the 1,000 samples of kid2, kid3 and kid6 were
// closest to another part (on kid6 its corners 40-57 units away along the surface, the folds 3-10); left
// there, they raised classical MDS's median pose RMS over the 28 pairs from 4.04% to 5.87%.
//
// Cost: an AABB tree on the remesh and a kd-tree on the input, O(n log n); per vertex a closest-point query
// and a bounded Dijkstra over the input vertices within about 10 remesh edges (on KIDS, ~60,000 vertices to
// 5,000: 1,000 samples in a fraction of a second).
#pragma once

#include <string>
#include <vector>

#include "cshapes/mesh/locate_on_surface.h"
#include "cshapes/mesh/mesh.h"

namespace cshapes {

struct RemeshSamples {
  std::vector<int> vertices;  // input vertex indices, as given
  SurfaceLocations at;        // where each lies on the remesh (rows in the order of `vertices`)
  double mean_distance = 0;   // mean ‖vertex − located point‖ / the input's bounding-box diagonal
  double max_distance = 0;    // the largest, likewise
  int relocated = 0;          // closest to another part, located on the closest triangle of their own
  int off_part = 0;           // closest to another part, with no triangle of their own within reach
};

// Carries `vertices` of `input` to `remesh` (a remesh of the same surface, faces of positive area). Throws
// cshapes::Error for a vertex index out of range or a remesh without faces.
RemeshSamples carry_to_remesh(const Mesh& input, const Mesh& remesh, const std::vector<int>& vertices);

// How far they moved, for the experiments' progress notes: "0.090% of the diagonal on average, at most
// 0.807%[, N relocated to their part][, M off their part]".
std::string carried_summary(const RemeshSamples& carried);

}  // namespace cshapes
