#include "cshapes/canon/coulomb_fmm_lists.h"

#include <cmath>

namespace cshapes::fmm_detail {
namespace {

class Traversal {
 public:
  Traversal(const std::vector<Cell>& cells, double opening_angle, int32_t cut, const ListStorage& lists)
      : cells_(cells), theta_(opening_angle), cut_(cut), m2l_(lists.m2l), p2p_(lists.p2p),
        deferred_(lists.scratch) {}

  // A serial pass stops at target cells of at most `cut` points and defers their pairs; then each deferred
  // target's pairs are traversed by one thread, in the serial pass's order. Deferred targets are disjoint
  // subtrees, and traverse(a, ·) writes only to lists of a's subtree, so the lists are the same as a serial
  // traversal's, whatever the thread count.
  void traverse_parallel() {
    deferred_.resize(cells_.size());
    for (auto& d : deferred_) d.clear();
    deferring_ = true;
    traverse(0, 0);
    deferring_ = false;
    std::vector<int32_t> targets;
    for (size_t a = 0; a < cells_.size(); ++a)
      if (!deferred_[a].empty()) targets.push_back(static_cast<int32_t>(a));
#pragma omp parallel for schedule(dynamic, 1)
    for (size_t t = 0; t < targets.size(); ++t)
      for (int32_t b : deferred_[targets[t]]) traverse(targets[t], b);
  }

  // Target a, source b: every ordered pair of points is covered exactly once, either by an M2L of b's
  // multipole into a's local expansion, or by a direct leaf-leaf sum.
  void traverse(int32_t a, int32_t b) {
    const Cell& A = cells_[a];
    const Cell& B = cells_[b];
    if (deferring_ && A.size() <= cut_) {
      deferred_[a].push_back(b);
      return;
    }
    if (a == b) {
      if (A.leaf()) {
        p2p_[a].push_back(a);
        return;
      }
      for (int32_t ca = A.child_begin; ca < A.child_begin + A.child_count; ++ca)
        for (int32_t cb = A.child_begin; cb < A.child_begin + A.child_count; ++cb) traverse(ca, cb);
      return;
    }
    if (separated(A, B)) {
      m2l_[a].push_back(b);
      return;
    }
    descend(a, b);
  }

  // traverse(a, b) for a pair of disjoint cells that are not well separated, a not deferred. Splitting b, the
  // children's separation is tested here (what traverse(a, child) would do first, the rest being known), so
  // the most frequent case, a child taken by M2L, costs no call.
  void descend(int32_t a, int32_t b) {
    const Cell& A = cells_[a];
    const Cell& B = cells_[b];
    if (A.leaf() && B.leaf()) {
      p2p_[a].push_back(b);
      return;
    }
    if (!A.leaf() && (B.leaf() || A.radius >= B.radius)) {
      for (int32_t ca = A.child_begin; ca < A.child_begin + A.child_count; ++ca) traverse(ca, b);
      return;
    }
    std::vector<int32_t>& m2l = m2l_[a];
    for (int32_t cb = B.child_begin; cb < B.child_begin + B.child_count; ++cb) {
      if (separated(A, cells_[cb]))
        m2l.push_back(cb);
      else
        descend(a, cb);
    }
  }

  bool separated(const Cell& A, const Cell& B) const {
    const double dx = A.center[0] - B.center[0], dy = A.center[1] - B.center[1],
                 dz = A.center[2] - B.center[2];
    return well_separated(A.radius + B.radius, dx * dx + dy * dy + dz * dz);
  }

 private:
  // Whether r_A + r_B < θ·√d2, exactly as that expression evaluates (the traversal's lists, and so every bit
  // of the sum, are those of the square-root test): squares decide when they are farther apart than their
  // rounding (a few ulps) could move them, the square root only in between or near underflow.
  bool well_separated(double radii, double d2) const {
    const double lhs = radii * radii, rhs = theta2_ * d2;
    if (rhs > 1e-280) {
      if (lhs < rhs * (1 - 1e-12)) return true;
      if (lhs > rhs * (1 + 1e-12)) return false;
    }
    return radii < theta_ * std::sqrt(d2);
  }

  const std::vector<Cell>& cells_;
  const double theta_, theta2_ = theta_ * theta_;
  const int32_t cut_;
  std::vector<std::vector<int32_t>>&m2l_, &p2p_, &deferred_;
  bool deferring_ = false;
};

}  // namespace

void make_interaction_lists(const std::vector<Cell>& cells, double opening_angle, int32_t cut,
                            const ListStorage& lists) {
  // A first evaluation allocates each list once instead of through a growth sequence (typical lists: ~60 M2L
  // sources per cell, ~30 near-field leaves per leaf at the default accuracy).
  if (lists.m2l.size() < cells.size()) {
    lists.m2l.resize(cells.size());
    lists.p2p.resize(cells.size());
  }
  for (size_t c = 0; c < cells.size(); ++c) {
    lists.m2l[c].clear();
    lists.p2p[c].clear();
    if (lists.m2l[c].capacity() == 0) lists.m2l[c].reserve(64);
    if (cells[c].leaf() && lists.p2p[c].capacity() == 0) lists.p2p[c].reserve(32);
  }
  Traversal(cells, opening_angle, cut, lists).traverse_parallel();
}

Index split_failing_pairs(const std::vector<Cell>& cells, double opening_angle, const ListStorage& lists) {
  Traversal traversal(cells, opening_angle, 0, lists);
  std::vector<std::vector<int32_t>>& failing = lists.scratch;  // by target cell
  failing.resize(cells.size());
  Index count = 0;
#pragma omp parallel for schedule(dynamic, 64) reduction(+ : count)
  for (size_t a = 0; a < cells.size(); ++a) {
    std::vector<int32_t>& list = lists.m2l[a];
    failing[a].clear();
    size_t kept = 0;
    for (int32_t b : list) {
      if (traversal.separated(cells[a], cells[b]))
        list[kept++] = b;
      else
        failing[a].push_back(b);
    }
    list.resize(kept);
    count += static_cast<Index>(failing[a].size());
  }
  for (size_t a = 0; a < cells.size(); ++a)
    for (int32_t b : failing[a]) traversal.descend(static_cast<int32_t>(a), b);
  return count;
}

}  // namespace cshapes::fmm_detail
