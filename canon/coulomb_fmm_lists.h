// The interaction lists of the fast multipole summation (canon/coulomb_fmm.h): for every target cell a, the
// source cells whose multipoles enter a's local expansion (M2L) and, at a leaf, the leaves summed directly
// with it (P2P). Made by a dual-tree traversal of the cells, or kept from an earlier evaluation of the same
// cells (CoulombFmmTree) and split where the points moved. Either way every ordered pair of points is covered
// exactly once, and the lists are the same for any thread count.
#pragma once

#include <cstdint>
#include <vector>

#include "cshapes/canon/coulomb_fmm_expansions.h"
#include "cshapes/support/types.h"

namespace cshapes::fmm_detail {

// The lists by target cell, and a scratch list per cell. Their capacity is kept from one evaluation to the
// next (cleared, not freed).
struct ListStorage {
  std::vector<std::vector<int32_t>>& m2l;
  std::vector<std::vector<int32_t>>& p2p;
  std::vector<std::vector<int32_t>>& scratch;
};

// The lists of `cells` (breadth first, parents before children) by a dual-tree traversal (Dehnen 2002): cells
// A, B interact through one M2L when r_A + r_B < θ·‖z_A − z_B‖ (θ: opening_angle), otherwise the larger is
// split; leaf pairs that stay close are summed directly. Below cells of at most `cut` points the traversal
// runs in parallel, each such cell's pairs on one thread.
void make_interaction_lists(const std::vector<Cell>& cells, double opening_angle, int32_t cut,
                            const ListStorage& lists);

// Lists made for the same cells at earlier positions, against their refit centres and radii: every M2L pair
// that no longer meets the opening criterion leaves its list and is split as the traversal would split it,
// in the order of the cells and of their lists; leaf pairs stay (their sums are exact). Returns the pairs
// split.
Index split_failing_pairs(const std::vector<Cell>& cells, double opening_angle, const ListStorage& lists);

}  // namespace cshapes::fmm_detail
