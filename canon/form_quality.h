// How sound a canonical form is, whatever method made it (Coulomb, classical MDS, SMACOF): how much its edges
// are stretched relative to the input, and which vertices ran away.
//
// A canonical form keeps the input's vertex order, so every edge (i, j) of the input's edge graph has an
// input length ‖v_i − v_j‖ and a canonical length ‖x_i − x_j‖; their ratio is the edge's stretch (1: length
// kept). Isometry-seeking methods keep it near 1 (Coulomb's fixed point inflates edges by ≈ 25% with the
// paper's step rule; MDS forms are in geodesic units, so stretches spread around 1). Torn edges (Coulomb,
// §2.2) are allowed to open and are left out of the statistics.
//
// A vertex is flagged as a runaway when any of these holds:
//   far:        it lies farther than far_diagonals × the input's bounding-box diagonal from the
//   coordinate-wise
//               median of the form (the median, unlike the centroid, stays put when a few vertices fly off);
//   stretched:  it ends an edge not torn whose canonical length exceeds overstretch × max(its input length,
//               the input's mean edge length) — the constraints did not hold it;
//   detached:   tearing cut it off: it lies outside the largest component, under the edges not torn, of the
//               component of the input graph it belongs to. Nothing but repulsion acts on such a part (in the
//               Coulomb iteration it drifts away for as long as the iteration runs).
//   coincident: it ends an edge of positive input length whose ends coincide in the form (‖x_i − x_j‖ at
//               most coincident_fraction × the form's bounding-box diagonal): a form collapsed to a point, or
//               part of one, can never pass (all-zero rows have diagonal 0, so every edge counts).
// Non-finite coordinates flag their vertex as far.
//
// Units: stretches are ratios; distances in the units of the input. Complexity: O(n + |E|) plus a partial
// sort of the |E| stretches for the 99th percentile.
#pragma once

#include <string>
#include <vector>

#include "cshapes/support/types.h"

namespace cshapes {

struct FormQualityOptions {
  double far_diagonals = 2.0;  // "far": beyond this many input bbox diagonals of the form's median
  double overstretch = 5.0;    // "stretched": a kept edge longer than this × max(own, mean) input length
  int listed = 10;             // how many runaway vertex indices FormQuality::runaway_examples keeps
  // "coincident": an edge shorter than this × the form's bbox diagonal (a few thousand rounding errors of
  // its coordinates: no isometry-seeking form brings two neighbours that close).
  double coincident_fraction = 1e-12;
};

struct FormQuality {
  // Stretch ‖x_i − x_j‖ / ‖v_i − v_j‖ over the edges not torn (edges of zero input length are skipped).
  double max_stretch = 0;
  double p99_stretch = 0;  // 99th percentile (nearest rank)
  double mean_stretch = 0;
  double min_stretch = 0;
  Index edges_measured = 0;       // edges that entered the statistics
  Index overstretched_edges = 0;  // kept edges over the "stretched" limit
  double max_distance = 0;        // farthest vertex from the form's median, in input bbox diagonals
  Index far_vertices = 0;
  Index stretched_vertices = 0;  // endpoints of overstretched edges
  Index detached_vertices = 0;
  Index coincident_vertices = 0;        // endpoints of edges whose ends coincide in the form
  Index runaway_vertices = 0;           // vertices with any of the four flags
  std::vector<Index> runaway_examples;  // the first FormQualityOptions::listed of them, increasing
  bool ok = true;                       // no runaway vertex and finite coordinates
  std::string description;              // one line, e.g. "ok: stretch max 1.84, p99 1.52, mean 1.24"
};

// input_V: n×3 input positions; E: |E|×2 edges of the input's edge graph (mesh edges or kNN graph); X: n×3
// canonical form in the same vertex order; torn_edges: null, or |E| flags (true: the edge was torn and is
// left out). Throws cshapes::Error when the sizes disagree or an edge index is out of range.
FormQuality form_quality(const Points& input_V, const Edges& E, const Points& X,
                         const std::vector<bool>* torn_edges = nullptr,
                         const FormQualityOptions& options = {});

// Marks a form not ok for a reason form_quality cannot see (e.g. a NaN stress from the method that made it):
// ok = false and the reason leads the description ("NOT OK: stress is NaN; ...").
void fail_form_quality(FormQuality& quality, const std::string& reason);

// The |E| torn flags of E for a list of torn edges (either orientation); edges of `torn` not in E are
// ignored.
std::vector<bool> torn_edge_flags(const Edges& E, const Edges& torn);

}  // namespace cshapes
