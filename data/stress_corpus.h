// A corpus of failure-prone triangle meshes made by code, for stress-testing every geometric method on the
// meshes real collections bring (remeshes at many sizes, jitter, needles and caps from edge flips, low-valence
// vertices with obtuse fans, nearly degenerate faces, long thin tubes, glued handles, boundaries, scales far
// from 1). Case i of seed s is always the same mesh: stress_case(s, i) draws its kind and parameters from a
// generator seeded by (s, i) alone, so any case can be rebuilt from the two numbers a stress run prints.
//
// Kinds cycle with i (i mod kinds), so any kStressKinds consecutive cases hold every kind. Sizes are drawn
// log-uniformly in [min_vertices, max_vertices] (a base shape is remeshed isotropically to a size below its
// own, refined by subdivision and edge splits to a size above it; the splits kind adds up to twice as many
// vertices again). Meshes are closed unless the kind says otherwise, manifold, in one component
// (handles and boundaries keep that), and may hold zero-area faces (kind near-degenerate) — no other defect.
// Cost: one CGAL remesh or one refinement per case plus O(n) for the perturbation.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "cshapes/mesh/mesh.h"

namespace cshapes {

enum class StressKind {
  Remesh,          // a generated or TOSCA shape remeshed (smaller) or refined (larger): the baseline
  Jitter,          // a remesh whose vertices moved by up to 45% of the local edge length
  Flips,           // random edge flips of a remesh: needles, caps, valence-3/4 vertices, obtuse fans
  Splits,          // faces split at points near a corner, edges split near an end: valence 3/4, slivers
  NearDegenerate,  // vertices moved onto the opposite edge (zero-area faces) or onto a neighbour (zero length)
  Tube,            // a long thin capsule, 3-8 vertices around, possibly bent and with split faces
  Handles,         // a shape with 1-4 glued handles (topological noise)
  Boundary,        // a shape with holes cut into it (boundary loops), or an open grid
  Scale,           // a remesh scaled by 1e-4 .. 1e4, with flips
};
constexpr int kStressKinds = 9;
std::string to_string(StressKind kind);

struct StressCorpusOptions {
  Index min_vertices = 200;    // size range of the base remesh (log-uniform)
  Index max_vertices = 30000;  // (see above)
  // TOSCA shapes to draw bases from (e.g. the folder of ../shared/data/tosca5k), besides the generated ones;
  // empty: generated bases only (icosphere, torus, capsule, the articulated classes).
  std::string tosca_folder;
};

struct StressCase {
  std::uint64_t seed = 0;
  Index index = 0;
  StressKind kind = StressKind::Remesh;
  std::string base;         // which shape it starts from ("torus", "articulated:hand", "tosca:cat0", ...)
  Index base_vertices = 0;  // the remesh size drawn
  double amount = 0;        // the kind's parameter (jitter fraction, flip fraction, scale, glues, holes, ...)
  std::string name() const;  // "s<seed>-i<index>-<kind>", a file name for the mesh
  std::string describe() const;
};

// The parameters of case `index` of `seed` (no mesh is made).
StressCase stress_case(std::uint64_t seed, Index index, const StressCorpusOptions& options = {});
// The corpus options' own checks (50 <= min_vertices <= max_vertices), which stress_case applies: throws
// Error naming both. For front ends, before any work (a case's error would only fail that case).
void check_stress_corpus_options(const StressCorpusOptions& options);

// The mesh of a case: deterministic for (seed, index, options).
Mesh make_stress_mesh(const StressCase& c, const StressCorpusOptions& options = {});

// Random edge flips (combinatorial: the new edge is the chord between the two opposite vertices, so the
// surface folds a little): about fraction × edges, skipping flips that would duplicate an edge or leave a
// vertex with fewer than 3 edges. Keeps the mesh closed/manifold where it was. Deterministic for a seed.
Mesh random_edge_flips(const Mesh& mesh, double fraction, std::uint64_t seed);

}  // namespace cshapes
