// Tearing (§2.2): which edges of the Coulomb iteration's edge graph a tear removes — the most violated ones,
// those the guard allows — with the choice made by the geometry: ties ordered by position, and a margin at
// the cut so that rounding cannot move an edge across it (a renumbered, rescaled or jittered input tears the
// same edges). Used by canon/coulomb.h's iteration and canon/coulomb_multiresolution.h's refinement.
#pragma once

#include <string>
#include <vector>

#include "cshapes/support/types.h"

namespace cshapes {

// Which tears select_edges_to_tear refuses. A part of the edge graph that tearing cuts off feels nothing but
// the repulsion of the rest: it drifts away for as long as the iteration runs, dragging the faces that joined
// it to the body across the form (a runaway; form_quality.h flags it). The vertex guard still cut parts off:
// hands of merged scans with real topological noise at the default options, and pairs of vertices or
// patches of most shapes at a larger tear fraction. The connected guard cut nothing off in all of these, and
// on the shapes the tearing defaults were tuned on its forms are the vertex guard's within a small fraction
// of a percent of the bbox diagonal, with the same glued bridges torn (the measurements:
// docs/coulomb-defaults.md, the defaults table, `--tear-guard`).
enum class TearGuard {
  Vertex,  // keep one edge at every vertex (the rule before the guard): a pair or patch may still be cut off
  Connected  // keep two edges at every vertex and never split a component of the edge graph
};
TearGuard parse_tear_guard(const std::string& name);  // "vertex" | "connected"
std::string to_string(TearGuard guard);

// The relative margin of select_edges_to_tear's cut: far above the rounding of the deviations (≈ 1e-16,
// grown by the iteration to ≈ 1e-10 between renumbered runs) and far below the gaps between distinct ones.
inline constexpr double kTearMargin = 1e-7;

// Selects the edges to tear: the `count` largest deviations |‖x_i − x_j‖ − d_ij|, skipping any edge the guard
// refuses given the edges already chosen — Vertex: one that would leave a vertex without edges; Connected:
// one that would leave a vertex with fewer than two edges (a vertex that already has fewer keeps them), or
// whose endpoints would no longer be joined by a path of remaining edges. Returns row indices into E, by
// decreasing deviation: `count` of them (fewer when the guard refuses the rest), and beyond `count` those
// whose deviation is within kTearMargin of the count-th one (ties, as on a symmetric mesh), so that rounding
// cannot move an edge across the cut — unless the count-th deviation is below kTearMargin × the mean rest
// length (edges that are not deformed are no ties). Equal deviations are ordered by the positions of the
// edges' ends in X (coordinates x, then y, then z), not by edge index: the choice is the same however the
// vertices and edges are numbered. Cost: one sort of |E|, plus for Connected a bidirectional breadth-first
// search per candidate, which stops at the smaller side (a few steps on a mesh, where the endpoints share a
// triangle).
std::vector<Index> select_edges_to_tear(const Points& X, const Edges& E, const Eigen::VectorXd& rest_lengths,
                                        Index num_vertices, Index count,
                                        TearGuard guard = TearGuard::Connected);

}  // namespace cshapes
