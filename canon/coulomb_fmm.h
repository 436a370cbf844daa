// Fast multipole summation of the Coulomb energy of eq. (1) and its gradient (see canon/coulomb_energy.h for
// the conventions: E = Σ_{i≠j} 1/r_ij over ordered pairs, ∇_i E = 2∇φ(x_i), distance floor).
//
// Method: an adaptive octree over the Morton-sorted points (leaves of at most leaf_size points, chains of
// single-child cells collapsed), Cartesian Taylor expansions of total order p about each cell's centre of
// mass (so the dipole term vanishes for unit charges), and a dual-tree traversal (Dehnen 2002, "falcON"): two
// cells A, B interact through one multipole-to-local translation when r_A + r_B < θ·‖z_A − z_B‖ (r = radius
// of the cell's points about its centre z), otherwise the larger cell is split; leaf pairs that stay close
// are summed directly with a float SIMD kernel (coulomb_p2p.h): at accuracy ≥ 3e-4 (and order ≤ 5) in local
// frames (float coordinates relative to each leaf's parent, pairs closer than 1/256 of that frame summed
// exactly in double), otherwise with exact float differences. Translations use the recurrence of Duan &
// Krasny for the Taylor coefficients of 1/r; orders 3–6 use unrolled compile-time kernels. Cost for fixed
// (p, θ): O(n) interactions plus an O(n · tree depth) pass for the cells' radii; memory O(n).
//
// Accuracy: `accuracy` is the target relative L2 error of the gradient, ‖g_fast − g_direct‖ / ‖g_direct‖;
// (p, θ, leaf size) are chosen from it by a table (coulomb_fmm_expansions.cpp, choose_parameters): for each
// accuracy the cheapest setting whose worst error stayed below it, with a margin, on the vertices of real
// meshes and on random points in a cube, on a sphere, in clusters and on a mesh's surface. The vertices of
// regular grids were the hardest case found (regular spacing, a cancelling gradient), and they too stayed
// below the default accuracy (the measurements: docs/coulomb-defaults.md, "The fast sum's parameters").
// Valid for accuracy in [3e-6, 1e-2]; the float near field bounds the attainable error at ≈ 1e-6, so
// smaller requests are served as 3e-6. The energy's relative error is smaller than the gradient's.
//
// Determinism: every target's sum is formed in a fixed order, so the output is bit-identical for identical
// inputs, and independent of the number of OpenMP threads. With a kept tree (CoulombFmmTree below), "inputs"
// are the points of every evaluation since the tree's last build.
#pragma once

#include <memory>

#include "cshapes/canon/coulomb_energy.h"

namespace cshapes {

struct CoulombFmmOptions {
  double accuracy = 1e-3;  // target relative L2 error of the gradient; picks order and opening_angle
  int order = 0;           // expansion order p (1 … 16); 0: chosen from accuracy
  // θ in (0, 1): cells interact by expansion when r_A + r_B < θ·distance; 0: chosen from accuracy
  double opening_angle = 0;
  int leaf_size = 0;             // most points in a leaf; 0: chosen from accuracy (48 or 96)
  double min_distance = 0;       // distance floor (see coulomb_energy.h); 0: 1e-9 × bounding-box diagonal
  bool want_potentials = false;  // also return the potentials φ_i
};

// What the FMM did, for benchmarks and tuning.
struct CoulombFmmStats {
  int order = 0;
  double opening_angle = 0;
  int leaf_size = 0;
  Index cells = 0, leaves = 0, tree_depth = 0;
  Index m2l_interactions = 0;  // multipole-to-local translations
  Index p2p_interactions = 0;  // point pairs summed directly
  // seconds_interactions: the M2L, near field, L2L and L2P (the downward pass runs with the interactions)
  double seconds_tree = 0, seconds_upward = 0, seconds_traversal = 0, seconds_interactions = 0;
  double seconds_m2l = 0, seconds_p2p = 0;  // inside seconds_interactions, summed over threads
  bool kept_tree = false;  // the evaluation kept a CoulombFmmTree's cells and lists (refit, not built)
  Index pairs_split = 0;   // with a kept tree: its M2L pairs that failed the opening criterion and were split
};

// The octree and interaction lists of one fast evaluation, kept for the next evaluations of as many points
// that moved a little (the Coulomb iteration moves a vertex by a fraction of an edge per step), so that they
// skip the Morton sort, the octree's construction and the dual-tree traversal. A kept tree keeps its cells
// (each the same points as when it was built) and refits every cell's centre and radius to the points' new
// positions; each kept M2L pair is tested against the opening criterion with the new radii, and a pair that
// fails it is split further as the traversal would, so every expansion meets the same criterion as in a fresh
// tree (the same error bound per interaction; leaf pairs summed directly stay exact). Lists only ever split,
// so their work grows as the points move: the tree is built afresh every `rebuild_every` evaluations, and
// whenever the point count or the parameters change. rebuild_every = 1 builds at every evaluation: the bytes
// of an evaluation without a tree. Deterministic: the outputs depend on the inputs since the last build, never
// on the thread count.
class CoulombFmmTree {
 public:
  explicit CoulombFmmTree(int rebuild_every = 1);
  ~CoulombFmmTree();
  CoulombFmmTree(CoulombFmmTree&&) noexcept;
  CoulombFmmTree& operator=(CoulombFmmTree&&) noexcept;
  int rebuild_every() const { return rebuild_every_; }
  Index builds() const;  // evaluations that built the tree
  Index kept() const;    // evaluations that kept it
  struct State;          // the cells, the lists and the counts (canon/coulomb_fmm.cpp)
  State& state() { return *state_; }

 private:
  int rebuild_every_;
  std::unique_ptr<State> state_;
};

// Energy, gradient (and potentials if asked) of the n×3 points X. O(n) for a fixed accuracy. tree: kept from
// one call to the next (see CoulombFmmTree), or none.
CoulombEvaluation coulomb_fmm(const Points& X, const CoulombFmmOptions& options = {},
                              CoulombFmmStats* stats = nullptr, CoulombFmmTree* tree = nullptr);

}  // namespace cshapes
