// Parts of a shape found from its intrinsic geometry alone: a geodesic centre, the extremities (the tips of
// limbs, head, tail) and the region around each, so that a per-part measure can say where something happens
// without anyone naming the parts.
//
//   1. Centre: the vertex with the smallest sum of geodesic distances to `centre_sources` evenly spaced
//      vertices (a sampled geodesic median, the vertex of least eccentricity in the L1 sense).
//   2. Extremities: the local maxima of the distance from the centre d_c whose topological persistence is at
//      least min_persistence · max d_c. Persistence (of superlevel sets of d_c): a maximum is born at its
//      value and dies where its region first joins a region with a higher maximum; the tip of a limb dies
//      where the limb meets the body (about the limb's length), a bump on the surface almost at once; the
//      farthest vertex never dies (its persistence is max d_c). Ordered farthest from the centre first; the
//      max_extremities most persistent when there are more. On a generated biped: head, two hands, two feet;
//      a quadruped: four legs, head, tail; a hand: five fingertips and the wrist.
//   3. Parts: vertex v belongs to the part of its geodesically nearest extremity e when d(v, e) <
//      part_fraction · d_c(e), else to the core (part 0). Parts are numbered 1, 2, ... in the order the
//      extremities were found (farthest first).
//
// Geodesics: options.geodesics (fast marching by default) on the mesh repaired to a manifold surface
// (mesh/mesh_repair.h: largest component, non-manifold vertices split, zero-area faces dropped), placed back
// at the input's vertices; a vertex the repair dropped has part −1 and infinite distances. Every threshold is
// relative to max d_c, so the parts are the same under a rigid motion or a scaling of the mesh (up to the
// floating-point ties of the geodesics). Cost: centre_sources + 1 + (extremities) single-source runs,
// O(n log n) each with fast marching, and one sort of the vertices.
//
// Limits: the parts are what the geometry says, not anatomy: a fist against the hip, or a limb merged with
// the body by topological noise, makes no extremity; a long flat bump (a heel, a long snout) may make one of
// its own. The names of the parts are their extremities' vertices, not "left hand".
#pragma once

#include <vector>

#include "cshapes/geodesics/geodesics.h"
#include "cshapes/mesh/mesh.h"

namespace cshapes {

struct GeodesicPartsOptions {
  int centre_sources = 32;        // evenly spaced vertices whose summed distances choose the centre (≥ 1)
  double min_persistence = 0.15;  // an extremity's persistence is at least this fraction of max d_c
  int max_extremities = 12;       // at most this many extremities (≥ 1)
  double part_fraction = 0.5;  // v in e's part when d(v, e) < part_fraction · d_c(e), e its nearest extremity
  // Geodesics for every distance above: fast marching (no set-up per source on a mesh this size).
  GeodesicOptions geodesics = [] {
    GeodesicOptions g;
    g.method = GeodesicMethod::FastMarching;
    return g;
  }();
};

struct GeodesicPartsResult {
  int centre = -1;               // vertex of the input
  std::vector<int> extremities;  // vertices of the input, in the order found (part k is extremities[k−1])
  Eigen::VectorXi part;  // per input vertex: 0 core, k ≥ 1 extremity k's part, −1 dropped by repair
  Eigen::VectorXd centre_distance;      // per input vertex: d_c, in the mesh's units (+inf where dropped)
  std::vector<double> extremity_reach;  // per extremity: d_c(e) / max d_c
  std::vector<double> extremity_persistence;  // per extremity: its persistence / max d_c
  double refused_persistence = 0;  // the largest persistence / max d_c of a maximum left out (0: none)
  std::string repair_text;         // what the repair for the geodesics did ("" when nothing)
  int part_count() const { return static_cast<int>(extremities.size()) + 1; }  // with the core
};

// The parts of `mesh` (see above). Throws when the mesh has no faces, or fewer than 4 vertices survive the
// repair, or an option is out of range.
GeodesicPartsResult geodesic_parts(const Mesh& mesh, const GeodesicPartsOptions& options = {});

}  // namespace cshapes
