// Coulomb canonical forms of fine meshes through a coarse one, so that the form is a property of the surface
// and not of its triangulation (issue 24).
//
// Why the single-level iteration depends on the resolution (the measurements: docs/notes.md, "MDS and
// Coulomb across resolutions"): each outer iteration moves a typical vertex by a fixed share of a mean edge h
// (the step rule), and k = 10 Jacobi sweeps of the averaged projection pull it back. The sweeps act like a
// diffusion of k steps over the edge graph: a deformation of wavelength λ is reduced by about k·(h/λ)² per
// iteration, so the shape-wide inflation (λ ≈ the shape's size R) is held by a force ∝ k h²/R² while the
// Coulomb step pushes by ∝ h. The fixed point's inflation grows like R/(k h) ∝ √n, as remeshes of one shape
// at growing vertex counts show (their median edge ratio). Scaling the step by h/R instead would need O(n)
// iterations, and scaling k by (R/h)² O(n) sweeps per iteration: the cost would grow like n².
//
// The method here: remesh the surface to coarse_vertices (mesh/remesh.h; the resolution the defaults were
// chosen at), run coulomb_canonical_form there, carry the coarse form to the fine vertices (prolongation:
// each fine vertex in the affine frame of its closest coarse triangle, [b−a, c−a, n], mapped into that
// triangle's frame in the coarse form), tear the fine edges the coarse tears opened (as many as keep the
// cut's length: the coarse tear count × h_coarse / h_fine, largest deviation first, the connected guard),
// then refine_iterations projections (each projection.steps Jacobi sweeps, metric_projection.h) on the fine
// edges, which restore the fine edge lengths locally while the shape-wide form stays the coarse one's (no
// Coulomb steps at the fine level: they would start its own, larger, inflation). Fine edges still stretched
// across a coarse gap after the sweeps (beyond the form quality's overstretch limit) are torn as well, by
// the same guard, and the sweeps repeated, up to 30 rounds (after the first 20, each with an eighth of the
// sweeps). The closest coarse triangle is the closest
// facing the fine vertex's way (normals), so that where two parts almost touch a vertex follows its own.
// Both were needed on fine meshes whose parts touch: before them, poses failed their quality check with many
// vertices on edges stretched across a gap; with them, every pose passes (the measurements:
// docs/coulomb-defaults.md, "The multiresolution switch", the fine level).
//
// Meshes whose resolution (area / (√3/2 · mean edge²): the inflation above grows with R/h̄, whatever the
// vertex count) is at most above_resolution, point clouds and meshes the remesher refuses (non-manifold) use
// the single-level iteration unchanged (and say why in the note). Cost: one remesh (O(n log n)), the coarse
// iteration, a closest-triangle search (kd-tree, O(n log n)), refine_iterations · k sweeps (O(|E|) each) and
// one fast Coulomb energy for the report.
#pragma once

#include <string>

#include "cshapes/canon/coulomb.h"
#include "cshapes/mesh/mesh.h"

namespace cshapes {

struct CoulombMultiresolutionResult {
  CoulombCanonResult result;  // on the fine mesh: X, torn edges (fine), the coarse iteration's history
  bool used = false;          // false: the single-level iteration ran (see note)
  Index coarse_vertices = 0;
  int coarse_iterations = 0;
  Index coarse_torn_edges = 0;
  int refine_rounds = 0;   // rounds of refine_iterations sweeps (1 + one per round of extra tears)
  Index extra_tears = 0;  // fine edges still overstretched after the sweeps, torn in later rounds (asked)
  double remesh_seconds = 0, coarse_seconds = 0, prolong_seconds = 0, refine_seconds = 0;
  std::string note;  // one line: what was done, or why not
};

// The Coulomb form of `mesh` (its edges and rest lengths from the mesh) by options.multiresolution's rule.
CoulombMultiresolutionResult coulomb_multiresolution(const Mesh& mesh, const CoulombCanonOptions& options);

// The prolongation alone: fine points P carried from the coarse surface (Vc, Fc) to its form Yc (both
// |Vc|×3): each point in the frame [b−a, c−a, n] of its closest coarse triangle, n the unit normal, mapped to
// [b'−a', c'−a', n'·√(area'/area)]. A point on the coarse surface lands on the coarse form's triangle.
// N: empty, or the points' unit normals (|P|×3): then the closest triangle whose normal faces the same way is
// taken when there is one among the candidates (the triangles of the 16 nearest coarse vertices), so that a
// point where two parts almost touch follows its own part and not the other (it leaves far fewer vertices
// on overstretched edges: docs/coulomb-defaults.md, "The multiresolution switch", the fine level).
Points prolong_to_fine(const Points& P, const Points& Vc, const Faces& Fc, const Points& Yc,
                       const Points& N = {});

}  // namespace cshapes
