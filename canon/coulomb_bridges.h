// Which torn edges were bridges: short cuts between parts of the surface that lie far apart along it (a
// glued tube of topological noise), as opposed to the edges that tearing opens within the surface.
//
// Why: a glued tube holds the parts it joins together from the first iteration until tearing opens it
// (from iteration tear_after), and by then the form has settled around it: the glued pose's form stays in
// another arrangement than its clean pose's even after the tube is torn. Knowing the bridges, the iteration
// can run again with them removed from the first iteration and from the start's graph
// (CoulombCanonOptions::bridge_detour).
//
// The test. Tearing opens cracks: the edges it removes cross a line on the surface, so each crack's torn
// edges are joined through shared vertices (consecutive crossed edges are two sides of one triangle). Going
// round a crack from one side to the other is at most about as long as the crack, and a crack that crosses
// k edges is about k edges long. A torn edge (a, b) is a bridge when, along the edges that remain after
// every tear, b is farther from a than both
//   - min_detour (the parts a bridge joins lie far apart along the surface), and
//   - k × the median edge length of E, k the number of torn edges joined to (a, b) through shared vertices
//     (its crack, or the tube and whatever tore next to it): a detour that its crack cannot explain; k is at
//     least kMinBridgeDetourEdges, because any torn edge has a detour of a few edges (1 + √2 round a triangle
//     of a regular mesh, up to about 5.5 among flipped edges). Without that floor, on meshes of a few hundred
//     vertices, where min_detour is only a few edges, clean shapes of the stress corpus "tore bridges" and
//     ran twice; with it, only the cases with glued handles do. The floor only removes bridges: the clean
//     shapes the default was chosen and judged on tore none, and on every glued one the default min_detour
//     (0.1 bbox diagonals) is longer than the floor, so it changes nothing there.
// Why both bounds: on the tuning data the crack's length separates the torn edges of clean poses from the
// tubes of their glued poses (data/topological_noise.h) with a wide gap, while the detour in diagonals alone
// does not (some torn edges of clean poses lie beyond the default min_detour). The measurements, and the
// stress corpus's cases: docs/coulomb-defaults.md, "Glued tubes".
// Cost: one Dijkstra per torn edge, stopped at the larger bound.
#pragma once

#include <vector>

#include "cshapes/support/types.h"

namespace cshapes {

// The least detour of a bridge, in median edges, whatever its crack (see above).
inline constexpr double kMinBridgeDetourEdges = 6;

// torn: rows of E removed. Returns the rows among them that are bridges (see above), in the order of
// `torn`; lengths are those of X0. min_detour > 0.
std::vector<Index> torn_bridges(const Points& X0, const Edges& E, const std::vector<Index>& torn,
                                double min_detour);

}  // namespace cshapes
