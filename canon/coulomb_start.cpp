#include "cshapes/canon/coulomb_start.h"

#include <algorithm>
#include <cmath>

#include "cshapes/canon/landmark_mds.h"
#include "cshapes/support/format.h"
#include "cshapes/support/error.h"
#include "cshapes/geodesics/landmark_geodesics.h"
#include "cshapes/mesh/mesh.h"
#include "cshapes/support/timing.h"

namespace cshapes {

CoulombStart parse_coulomb_start(const std::string& name) {
  if (name == "input") return CoulombStart::Input;
  if (name == "landmark-mds") return CoulombStart::LandmarkMds;
  fail("unknown Coulomb start '", name, "'; known: landmark-mds, input");
}

std::string to_string(CoulombStart start) {
  return start == CoulombStart::Input ? "input" : "landmark-mds";
}


StartLandmarks start_landmarks(const Points& X0, const SingleSourceGeodesics& graph, Index count) {
  const Index n = X0.rows();
  CSHAPES_REQUIRE(graph.num_vertices() == n, "coulomb start: ", graph.num_vertices(), " graph vertices for ",
                  n, " points");
  const Index L = std::min(count, n);
  StartLandmarks result;
  result.rows.resize(L, n);
  // The sampling starts from one end of a long geodesic: the vertex farthest from the one farthest from the
  // central vertex (a double sweep; its first landmark is the vertex farthest from that end).
  const Index far_end = argmax_by_position(graph.distances(static_cast<int>(central_vertex(X0))), X0);
  Eigen::VectorXd nearest = graph.distances(static_cast<int>(far_end));
  for (Index k = 0; k < L; ++k) {
    const Index next = argmax_by_position(nearest, X0);
    result.landmarks.push_back(static_cast<int>(next));
    const Eigen::VectorXd row = graph.distances(static_cast<int>(next));
    result.rows.row(k) = row.transpose();
    nearest = k == 0 ? row : nearest.cwiseMin(row);
  }
  return result;
}

CoulombStartResult coulomb_start(const Points& X0, const Edges& E, CoulombStart start, Index landmarks) {
  const auto begin = WallClock::now();
  CoulombStartResult result;
  auto input = [&](const std::string& why) {
    result.X = X0;
    result.used = start == CoulombStart::Input;
    result.note = why;
    result.seconds = seconds_since(begin);
    return result;
  };
  if (start == CoulombStart::Input) return input("the input's coordinates");
  const Index n = X0.rows();
  CSHAPES_REQUIRE(landmarks >= 4, "coulomb start: need at least 4 landmarks, not ", landmarks);
  if (n < 4) return input("the input's coordinates (fewer than 4 points for a landmark MDS start)");
  const Components components = connected_components(n, E);
  if (components.count != 1)
    return input("the input's coordinates (the edge graph has " + std::to_string(components.count) +
                 " components: no geodesic distance between them)");
  const SingleSourceGeodesics graph(X0, E);
  const StartLandmarks rows = start_landmarks(X0, graph, landmarks);
  if (!rows.rows.allFinite())
    return input("the input's coordinates (a landmark's graph distances are not finite)");
  const LandmarkMdsResult mds = landmark_classical_mds_double(rows.rows, rows.landmarks);
  if (!(mds.eigenvalues(2) > 0) || !mds.X.allFinite())
    return input("the input's coordinates (the landmarks' distances span fewer than three dimensions)");
  // The input's mean edge length: the embedding of graph distances is a little larger than the surface
  // (graph paths zigzag) and its edges are distorted, so its scale is set by the edges it will be held to.
  const double target = edge_lengths(X0, E).mean();
  const double current = edge_lengths(mds.X, E).mean();
  if (!(current > 0) || !(target > 0))
    return input("the input's coordinates (edges of length zero in the landmark MDS embedding)");
  // The start stays in the embedding's own frame (principal axes of the landmarks' distances), a function of
  // the distances alone: rotated into the input's frame, the iteration's sums (their order, the fast sum's
  // octree) would follow the input's orientation, and a rigid motion of the input would lead to another form.
  // coulomb_canonical_form turns the finished form onto the input.
  result.X = mds.X * (target / current);
  result.used = true;
  result.seconds = seconds_since(begin);
  result.note = "landmark MDS of graph geodesics from " + std::to_string(rows.landmarks.size()) +
                " landmarks (" + significant(result.seconds) + " s)";
  return result;
}

}  // namespace cshapes
