// Where the Coulomb iteration starts. The paper starts at the input's coordinates ("having a good
// initialization (the original shape vertex coordinates), we observe good convergence behavior"); on bodies
// that start keeps the pose. The Coulomb energy of a limb barely changes as it swings about its joint once
// it points away from the rest of the shape, so the iteration leaves each limb at about the angle it started
// at: the form is a fixed point near the start, not the minimum of an energy shared by every pose
// (docs/coulomb-defaults.md, "Start and flatten"). Started from a configuration that is
// itself the same for every pose, the fixed points of two poses are the same one.
//
//   Input        the input's coordinates (the paper)
//   LandmarkMds  landmark classical MDS (canon/landmark_mds.h) of the shortest-path distances along the
//                iteration's own edge graph, weighted by the input's edge lengths, from L farthest-point
//                landmarks: an embedding that depends on the surface's intrinsic geometry and not on its
//                pose. Scaled so that its mean edge length is the input's, and left in its own frame (the
//                landmarks' principal axes), so that the iteration does not depend on the input's orientation;
//                coulomb_canonical_form turns the finished form onto the input.
//
// Graph distances rather than the heat method: they need only the edges (a point cloud's kNN graph works as
// a mesh's) and their metrication error (a few % along oblique directions) is harmless for a start that the
// iteration then relaxes; on the tuning data heat-method rows gave the same pose invariance
// (docs/coulomb-defaults.md, "Start and flatten"). No n×n matrix: L rows of n doubles. Cost O(L·|E| log n)
// for L Dijkstra runs, O(L·n) for the triangulation of the other points.
//
// The graph must be connected and the landmarks' distances must span three dimensions; otherwise the start
// falls back to the input, and the note says why.
#pragma once

#include <string>
#include <vector>

#include "cshapes/support/types.h"

namespace cshapes {

enum class CoulombStart {
  Input,       // the input's coordinates (the paper)
  LandmarkMds  // landmark classical MDS of graph geodesics (see above)
};
CoulombStart parse_coulomb_start(const std::string& name);  // "input" | "landmark-mds"
std::string to_string(CoulombStart start);

struct CoulombStartResult {
  Points X;          // n×3 start, in the input's units: the input itself, or the embedding in its own frame
  bool used = true;  // false: the input, because the landmark MDS start could not be made (see note)
  std::string note;  // one line: what the start is, or why it fell back to the input
  double seconds = 0;
};

// The landmarks of the LandmarkMds start and their rows of graph distances, in double precision (float rows
// round a scaled copy's distances differently, and the iteration carries a start's differences into its form:
// docs/coulomb-defaults.md, "A function of the shape"). Farthest-point sampling from one end of a long
// geodesic — the vertex farthest from the vertex farthest from the one nearest the centroid — not from a
// vertex number; exact ties go to the vertex with the smallest coordinates (x, then y, then z). So the
// landmarks, and the start, are the same however the vertices are numbered. count: L, clamped to n.
struct StartLandmarks {
  std::vector<int> landmarks;  // L vertex indices, in the order of the sampling
  Eigen::MatrixXd rows;        // L × n: rows(k, j) = graph distance from landmarks[k] to vertex j
};
class SingleSourceGeodesics;  // geodesics/landmark_geodesics.h
StartLandmarks start_landmarks(const Points& X0, const SingleSourceGeodesics& graph, Index count);

// The start for the iteration on points X0 joined by edges E (0-based rows into X0). landmarks: L, clamped
// to n.
CoulombStartResult coulomb_start(const Points& X0, const Edges& E, CoulombStart start, Index landmarks);

}  // namespace cshapes
