#include "cshapes/canon/coulomb_fmm.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <memory>
#include <mutex>
#include <vector>

#include "cshapes/canon/coulomb_fmm_expansions.h"
#include "cshapes/canon/coulomb_fmm_lists.h"
#include "cshapes/canon/coulomb_p2p.h"
#include "cshapes/support/error.h"
#include "cshapes/support/morton.h"
#include "cshapes/support/simd.h"
#include "cshapes/support/timing.h"

namespace cshapes {

// A kept tree: the point order and cells of its last build, the lists of its last evaluation, and what they
// were built for.
struct CoulombFmmTree::State {
  Index n = -1;  // points of the last evaluation; -1: nothing kept
  fmm_detail::FmmParameters parameters{};
  int evaluations_since_build = 0;
  Index builds = 0, kept = 0;  // evaluations that built the tree, that kept it
  std::vector<int32_t> order;
  std::vector<fmm_detail::Cell> cells;
  std::vector<int32_t> depth_start;
  std::vector<std::vector<int32_t>> m2l, p2p;
};

CoulombFmmTree::CoulombFmmTree(int rebuild_every)
    : rebuild_every_(rebuild_every), state_(std::make_unique<State>()) {
  CSHAPES_REQUIRE(rebuild_every >= 1, "Coulomb FMM: rebuild_every must be >= 1, got ", rebuild_every);
}
CoulombFmmTree::~CoulombFmmTree() = default;
Index CoulombFmmTree::builds() const { return state_->builds; }
Index CoulombFmmTree::kept() const { return state_->kept; }
CoulombFmmTree::CoulombFmmTree(CoulombFmmTree&&) noexcept = default;
CoulombFmmTree& CoulombFmmTree::operator=(CoulombFmmTree&&) noexcept = default;

namespace {

using coulomb_detail::FloatPoints;
using coulomb_detail::FramedRange;
using coulomb_detail::kBlock;
using coulomb_detail::SourceRange;
using namespace fmm_detail;

class Fmm {
 public:
  // time_kernels: also time the M2L and P2P work of every cell (stats.seconds_m2l, seconds_p2p), two clock
  // reads per cell, for benchmarks; the phases are always timed.
  // tree: kept between evaluations, or null (the calling thread's workspace holds the cells and lists).
  Fmm(const Points& X, const FmmParameters& parameters, double min_distance, CoulombFmmStats& stats,
      bool time_kernels, CoulombFmmTree* tree)
      : X_(X),
        n_(X.rows()),
        tables_(tables_of_order(parameters.order)),
        stride_((tables_.count + 3) / 4 * 4),
        zero_moments_(stride_, 0.0),
        parameters_(parameters),
        theta_(parameters.opening_angle),
        leaf_size_(parameters.leaf_size),
        framed_near_field_(parameters.framed_near_field),
        refined_estimate_(parameters.refined_estimate),
        stats_(stats),
        time_kernels_(time_kernels),
        tree_(tree),
        keep_(tree && keepable(*tree, X.rows(), parameters)),
        order_(tree ? tree->state().order : work_.order),
        cells_(tree ? tree->state().cells : work_.cells),
        depth_start_(tree ? tree->state().depth_start : work_.depth_start),
        m2l_lists_(tree ? tree->state().m2l : list_store().m2l),
        p2p_lists_(tree ? tree->state().p2p : list_store().p2p) {
    norm_ = coulomb_detail::normalize_points(X, min_distance);
  }

  ~Fmm() {
    if (!tree_ && cells_.size() > kKeptListCells) list_store() = ListStore{};
    if (n_ > kKeptWorkspacePoints) workspace() = Workspace{};
  }

  CoulombEvaluation run(bool want_potentials) {
    // Until this evaluation's lists are complete the tree holds nothing to keep (an exception half way
    // leaves no half-split lists for the next evaluation).
    if (tree_) tree_->state().n = -1;
    auto t = WallClock::now();
    build_tree();
    find_subtrees();
    stats_.seconds_tree = seconds_since(t);
    t = WallClock::now();
    upward_pass();
    stats_.seconds_upward = seconds_since(t);
    t = WallClock::now();
    const ListStorage lists{m2l_lists_, p2p_lists_, deferred_};
    if (keep_)
      stats_.pairs_split = split_failing_pairs(cells_, theta_, lists);
    else
      make_interaction_lists(cells_, theta_, cut_, lists);
    stats_.seconds_traversal = seconds_since(t);
    stats_.kept_tree = keep_;
    if (tree_) {
      CoulombFmmTree::State& state = tree_->state();
      state.n = n_;
      state.parameters = parameters_;
      state.evaluations_since_build = keep_ ? state.evaluations_since_build + 1 : 0;
      ++(keep_ ? state.kept : state.builds);
    }
    t = WallClock::now();
    interactions_and_downward();
    stats_.seconds_interactions = seconds_since(t);
    return gather(want_potentials);
  }

 private:
  // Whether the tree's cells and lists can serve this evaluation: built for as many points with the same
  // parameters, fewer than rebuild_every evaluations ago.
  static bool keepable(CoulombFmmTree& tree, Index n, const FmmParameters& p) {
    const CoulombFmmTree::State& s = tree.state();
    const FmmParameters& q = s.parameters;
    return s.n == n && s.evaluations_since_build + 1 < tree.rebuild_every() && q.order == p.order &&
           q.opening_angle == p.opening_angle && q.leaf_size == p.leaf_size &&
           q.framed_near_field == p.framed_near_field && q.refined_estimate == p.refined_estimate;
  }

  void build_tree() {
    sort_points();
    if (!keep_) build_cells();
    cell_geometry();
    stats_.cells = static_cast<Index>(cells_.size());
    stats_.tree_depth = static_cast<Index>(depth_start_.size()) - 1;
    stats_.leaves = std::count_if(cells_.begin(), cells_.end(), [](const Cell& c) { return c.leaf(); });
  }

  // The points in Morton order (order_, keys_) with their normalized coordinates, and the near field's float
  // copies when it does not use leaf frames.
  void sort_points() {
    // Morton keys on a 2^21 grid over the normalized cube [-1, 1]³; sorting by (key, index) is deterministic.
    std::vector<std::pair<uint64_t, int32_t>>& keyed = work_.keyed;
    keyed.resize(n_);
    const double cells_per_unit = 0.5 * double(1 << kMortonLevels);
    // The normalized coordinates in input order (reordered below, not computed twice).
    std::vector<double>& unit = work_.unit;
    unit.resize(3 * static_cast<size_t>(n_));
#pragma omp parallel for schedule(static)
    for (Index i = 0; i < n_; ++i) {
      uint64_t key = 0;
      for (int c = 0; c < 3; ++c) {
        const double u = (X_(i, c) - norm_.center[c]) / norm_.scale;
        unit[3 * i + c] = u;
        // floor, then clamp to the grid: for a finite value the same as clamping first and truncating
        // (which is floor on [0, max]), without SSE2's slow floor and unsigned conversion.
        const double g = std::clamp((u + 1) * cells_per_unit, 0.0, double((1 << kMortonLevels) - 1));
        key |= morton_spread_bits(static_cast<uint64_t>(static_cast<int64_t>(g))) << (2 - c);
      }
      keyed[i] = {key, static_cast<int32_t>(i)};
    }
    // A kept tree keeps its order (its cells are ranges of it); otherwise the order of std::sort on the pairs.
    if (!keep_) radix_sort_by_key(keyed, 3 * kMortonLevels, &work_.keyed_scratch);
    order_.resize(n_);
    keys_.resize(n_);
    xd_.resize(n_), yd_.resize(n_), zd_.resize(n_);
    if (framed_near_field_) {
      xs_.resize(n_), ys_.resize(n_), zs_.resize(n_);
    } else {
      xf_.resize(n_), yf_.resize(n_), zf_.resize(n_), xl_.resize(n_), yl_.resize(n_), zl_.resize(n_);
    }
#pragma omp parallel for schedule(static)
    for (Index s = 0; s < n_; ++s) {
      const Index i = keep_ ? order_[s] : keyed[s].second;
      if (!keep_) order_[s] = static_cast<int32_t>(i), keys_[s] = keyed[s].first;
      xd_[s] = unit[3 * i], yd_[s] = unit[3 * i + 1], zd_[s] = unit[3 * i + 2];
      if (!framed_near_field_) {
        coulomb_detail::split_float(xd_[s], xf_[s], xl_[s]);
        coulomb_detail::split_float(yd_[s], yf_[s], yl_[s]);
        coulomb_detail::split_float(zd_[s], zf_[s], zl_[s]);
      }
    }
  }

  // The octree over the sorted keys, breadth first, single-child chains collapsed; depth_start_.
  void build_cells() {
    // Breadth-first: parents precede children, siblings are contiguous, depth never decreases.
    cells_.clear();
    std::vector<int> morton_level;  // octree level at which each cell's points start to differ
    Cell root;
    root.begin = 0, root.end = static_cast<int32_t>(n_);
    cells_.push_back(root);
    morton_level.push_back(0);
    for (size_t c = 0; c < cells_.size(); ++c) {
      const int32_t begin = cells_[c].begin, end = cells_[c].end;
      if (end - begin <= leaf_size_) continue;
      for (int level = morton_level[c]; level < kMortonLevels; ++level) {
        const int shift = 3 * (kMortonLevels - 1 - level);
        std::array<int32_t, 9> bound;
        bound[0] = begin;
        for (int o = 0; o < 8; ++o)
          bound[o + 1] = static_cast<int32_t>(
              std::partition_point(keys_.begin() + bound[o], keys_.begin() + end,
                                   [&](uint64_t k) { return static_cast<int>((k >> shift) & 7) <= o; }) -
              keys_.begin());
        int nonempty = 0;
        for (int o = 0; o < 8; ++o) nonempty += bound[o + 1] > bound[o];
        if (nonempty < 2) continue;  // a chain of single-child cells: skip the level
        cells_[c].child_begin = static_cast<int32_t>(cells_.size());
        for (int o = 0; o < 8; ++o) {
          if (bound[o + 1] == bound[o]) continue;
          Cell child;
          child.begin = bound[o], child.end = bound[o + 1];
          child.parent = static_cast<int32_t>(c);
          child.depth = cells_[c].depth + 1;
          cells_.push_back(child);
          morton_level.push_back(level + 1);
        }
        cells_[c].child_count = static_cast<int32_t>(cells_.size()) - cells_[c].child_begin;
        break;
      }
    }
    depth_start_.assign(1, 0);
    for (size_t c = 1; c < cells_.size(); ++c)
      if (cells_[c].depth != cells_[c - 1].depth) depth_start_.push_back(static_cast<int32_t>(c));
    depth_start_.push_back(static_cast<int32_t>(cells_.size()));
  }

  // Each cell's centre of mass and radius, and the leaves' near-field coordinates in their frames.
  void cell_geometry() {
    // Centres of mass bottom-up, then the exact radius of each cell's points (O(n · depth)).
    for (size_t c = cells_.size(); c-- > 0;) {
      Cell& cell = cells_[c];
      double s[3] = {0, 0, 0};
      if (cell.leaf()) {
        for (int32_t i = cell.begin; i < cell.end; ++i) s[0] += xd_[i], s[1] += yd_[i], s[2] += zd_[i];
      } else {
        for (int32_t ch = cell.child_begin; ch < cell.child_begin + cell.child_count; ++ch)
          for (int k = 0; k < 3; ++k) s[k] += cells_[ch].center[k] * cells_[ch].size();
      }
      for (int k = 0; k < 3; ++k) cell.center[k] = s[k] / cell.size();
    }
#pragma omp parallel for schedule(dynamic, 16)
    for (size_t c = 0; c < cells_.size(); ++c) {
      Cell& cell = cells_[c];
      double r2 = 0;
      for (int32_t i = cell.begin; i < cell.end; ++i) {
        const double dx = xd_[i] - cell.center[0], dy = yd_[i] - cell.center[1], dz = zd_[i] - cell.center[2];
        r2 = std::max(r2, dx * dx + dy * dy + dz * dz);
      }
      cell.radius = std::sqrt(r2);
      if (framed_near_field_ && cell.leaf()) {  // the near field's float coordinates (coulomb_p2p.h)
        const Cell& frame = cells_[frame_cell(static_cast<int32_t>(c))];
        for (int32_t i = cell.begin; i < cell.end; ++i) {
          xs_[i] = coulomb_detail::frame_coordinate(xd_[i], frame.center[0]);
          ys_[i] = coulomb_detail::frame_coordinate(yd_[i], frame.center[1]);
          zs_[i] = coulomb_detail::frame_coordinate(zd_[i], frame.center[2]);
        }
      }
    }
  }

  // The frame of a leaf's near-field coordinates: its parent (the root for a single-leaf tree), so that
  // consecutive sibling leaves in a near-field list form one source range of one frame. Differences keep
  // ~1e-7 of the parent's size.
  int32_t frame_cell(int32_t leaf) const {
    return cells_[leaf].parent >= 0 ? cells_[leaf].parent : leaf;
  }

  // The subtrees the parallel passes hand out whole: the largest cells of at most cut_ points, and the leaves
  // of more (coincident points no octree level separates), so that every point is in exactly one; cut_ =
  // n/32 (at least a leaf). top_: the cells above them, in index order (parents first). The traversal defers
  // its pairs at the same cells.
  void find_subtrees() {
    cut_ = std::max<int32_t>(static_cast<int32_t>(n_ / 32), leaf_size_);
    subtrees_.clear(), top_.clear();
    for (size_t c = 0; c < cells_.size(); ++c) {
      const Cell& cell = cells_[c];
      if (cell.size() > cut_ && !cell.leaf())
        top_.push_back(static_cast<int32_t>(c));
      else if (cell.parent < 0 || cells_[cell.parent].size() > cut_)
        subtrees_.push_back(static_cast<int32_t>(c));
    }
  }

  double* multipole(size_t c) {
    return multipoles_.data() + c * stride_;
  }
  double* local(size_t c) {
    return locals_.data() + c * stride_;
  }

  // Few parallel regions on purpose: on a shared, oversubscribed machine every OpenMP barrier can cost a
  // scheduler time slice. Each subtree's P2M and M2M run as one task; then the few cells above them, serially.
  void upward_pass() {
    const int count = tables_.count;
    multipoles_.assign(cells_.size() * stride_, 0.0);
    locals_.assign(cells_.size() * stride_, 0.0);
#pragma omp parallel
    {
      std::vector<double> mono(count);
#pragma omp for schedule(dynamic, 1)
      for (size_t t = 0; t < subtrees_.size(); ++t) upward_subtree(subtrees_[t], mono);
    }
    std::vector<double> mono(count);
    for (size_t t = top_.size(); t-- > 0;) m2m(top_[t], mono);
    // Store (−1)^|k| M_k: the sign of the source offset in the Taylor expansion, applied once. (After the
    // M2M pass, which needs the unsigned moments of every child.)
    for (size_t c = 0; c < cells_.size(); ++c) {
      double* M = multipole(c);
      for (int k = 0; k < count; ++k) M[k] *= tables_.sign[k];
    }
  }

  // P2M at the leaves of cell c's subtree, then M2M up to c: children before parents, each parent's children
  // in order. mono: the thread's scratch.
  void upward_subtree(int32_t c, std::vector<double>& mono) {
    const Cell& cell = cells_[c];
    if (cell.leaf()) {
      p2m(c, mono);
      return;
    }
    for (int32_t ch = cell.child_begin; ch < cell.child_begin + cell.child_count; ++ch) upward_subtree(ch, mono);
    m2m(c, mono);
  }

  void p2m(int32_t c, std::vector<double>& mono) {
    p2m_cell(tables_, cells_[c], xd_.data(), yd_.data(), zd_.data(), multipole(c), mono.data());
  }

  // M2M into c from its children, in order.
  void m2m(int32_t c, std::vector<double>& mono) {
    const Cell& cell = cells_[c];
    for (int32_t ch = cell.child_begin; ch < cell.child_begin + cell.child_count; ++ch) {
      const double s3[3] = {cells_[ch].center[0] - cell.center[0], cells_[ch].center[1] - cell.center[1],
                            cells_[ch].center[2] - cell.center[2]};
      m2m_shift(tables_, s3, multipole(ch), multipole(c), mono.data());
    }
  }

  // L2L into c from its parent.
  void l2l(int32_t c, std::vector<double>& mono) {
    const Cell& cell = cells_[c];
    const Cell& parent = cells_[cell.parent];
    const double t3[3] = {cell.center[0] - parent.center[0], cell.center[1] - parent.center[1],
                          cell.center[2] - parent.center[2]};
    l2l_shift(tables_, t3, local(cell.parent), local(c), mono.data());
  }

  void l2p(int32_t c, std::vector<double>& mono) {
    l2p_cell(tables_, cells_[c], xd_.data(), yd_.data(), zd_.data(), local(c), potential_.data(), fx_.data(),
             fy_.data(), fz_.data(), mono.data());
  }

  // Per thread: the scratch of the interactions, and its counts and kernel times.
  struct InteractionScratch {
    std::vector<V4> derivative, moments, accumulated;
    std::vector<FramedRange> ranges;
    std::vector<SourceRange> exact_ranges;
    std::vector<double> mono;
    Index m2l_total = 0, p2p_total = 0;
    double m2l_seconds = 0, p2p_seconds = 0;
  };

  // The M2L of the cells above the subtrees and their L2L (serially, parents first); then each subtree as one
  // task, top down: a cell's M2L, then its parent's local shifted in (L2L), and at a leaf its near field and
  // its local expansion at its points (L2P). Every local sums its M2L terms before its L2L terms and every
  // point gets one near-field and one L2P addition (in either order, the same double), as in the passes
  // one after the other: the same bytes, without their serial L2L and with one parallel region less.
  void interactions_and_downward() {
    potential_.assign(n_, 0.0), fx_.assign(n_, 0.0), fy_.assign(n_, 0.0), fz_.assign(n_, 0.0);
    Index m2l_total = 0, p2p_total = 0;
    double m2l_seconds = 0, p2p_seconds = 0;
#pragma omp parallel reduction(+ : m2l_total, p2p_total, m2l_seconds, p2p_seconds)
    {
      InteractionScratch scratch;
      scratch.derivative.resize(tables_.count), scratch.moments.resize(stride_);
      scratch.accumulated.resize(tables_.count), scratch.mono.resize(tables_.count);
#pragma omp for schedule(dynamic, 1)
      for (size_t t = 0; t < top_.size(); ++t) m2l(top_[t], scratch);
#pragma omp single
      for (int32_t c : top_)
        if (cells_[c].parent >= 0) l2l(c, scratch.mono);
#pragma omp for schedule(dynamic, 1)
      for (size_t t = 0; t < subtrees_.size(); ++t) subtree_interactions(subtrees_[t], scratch);
      m2l_total += scratch.m2l_total, p2p_total += scratch.p2p_total;
      m2l_seconds += scratch.m2l_seconds, p2p_seconds += scratch.p2p_seconds;
    }
    stats_.seconds_m2l = m2l_seconds;
    stats_.seconds_p2p = p2p_seconds;
    stats_.m2l_interactions = m2l_total;
    stats_.p2p_interactions = p2p_total;
  }

  void subtree_interactions(int32_t c, InteractionScratch& scratch) {
    m2l(c, scratch);
    if (cells_[c].parent >= 0) l2l(c, scratch.mono);
    const Cell& cell = cells_[c];
    if (cell.leaf()) {
      if (!p2p_lists_[c].empty()) {
        const auto p2p_start = time_kernels_ ? WallClock::now() : WallClock::time_point{};
        scratch.p2p_total += near_field(c, scratch.ranges, scratch.exact_ranges);
        if (time_kernels_) scratch.p2p_seconds += seconds_since(p2p_start);
      }
      l2p(c, scratch.mono);
      return;
    }
    for (int32_t ch = cell.child_begin; ch < cell.child_begin + cell.child_count; ++ch)
      subtree_interactions(ch, scratch);
  }

  // M2L: L_m += Σ_k (−1)^|k| M_k ∂^{m+k}(1/r)(z_a − z_b), four sources b per pass, one per lane; the lanes
  // are summed at the end in a fixed order (canon/coulomb_m2l_simd.inl for orders ≤ 6).
  void m2l(int32_t a, InteractionScratch& scratch) {
    const std::vector<int32_t>& list = m2l_lists_[a];
    if (list.empty()) return;
    const auto m2l_start = time_kernels_ ? WallClock::now() : WallClock::time_point{};
    if (const M2LCellFunction fixed = m2l_cell_kernel(tables_.order))
      fixed(cells_[a].center, list.data(), list.size(), cells_.data(), multipoles_.data(), stride_, local(a));
    else  // orders above 6: the table-driven loop
      m2l_table_driven(tables_, cells_[a].center, list, cells_.data(), multipoles_.data(), stride_,
                       zero_moments_.data(), scratch.derivative, scratch.moments, scratch.accumulated, local(a));
    scratch.m2l_total += static_cast<Index>(list.size());
    if (time_kernels_) scratch.m2l_seconds += seconds_since(m2l_start);
  }

  // The near field of leaf a: the direct sums from the leaves of its list, grouped into source ranges (a run
  // of sibling leaves is one range of one frame). Returns the pairs summed. The vectors are the thread's
  // scratch.
  Index near_field(int32_t a, std::vector<FramedRange>& ranges, std::vector<SourceRange>& exact_ranges) {
    const Cell& A = cells_[a];
    ranges.clear(), exact_ranges.clear();
    Index sources = 0;
    int self_range = -1;
    int32_t last_frame = -1;
    for (int32_t b : p2p_lists_[a]) {
      const Cell& B = cells_[b];
      const int32_t frame = frame_cell(b);
      if (frame == last_frame && ranges.back().end == B.begin) {  // a following sibling: one longer range
        ranges.back().end = B.end;
      } else {
        const Cell& F = cells_[frame];
        ranges.push_back({{F.center[0], F.center[1], F.center[2]},
                          B.begin,
                          B.end,
                          coulomb_detail::frame_close_h(F.radius)});
        last_frame = frame;
      }
      if (b == static_cast<int32_t>(a)) self_range = static_cast<int>(ranges.size()) - 1;
      exact_ranges.push_back({B.begin, B.end});
      sources += B.size();
    }
    if (!framed_near_field_) {
      const FloatPoints points{xf_.data(), yf_.data(), zf_.data(), xl_.data(), yl_.data(), zl_.data()};
      for (int32_t i0 = A.begin; i0 < A.end; i0 += kBlock)
        coulomb_detail::p2p_block(points, i0, std::min<int32_t>(kBlock, A.end - i0), exact_ranges.data(),
                                  static_cast<int>(exact_ranges.size()), norm_.floor2, potential_.data(),
                                  fx_.data(), fy_.data(), fz_.data());
    } else {
      for (int32_t i0 = A.begin; i0 < A.end; i0 += kBlock)
        coulomb_detail::p2p_framed_block(
            xd_.data(), yd_.data(), zd_.data(), i0, std::min<int32_t>(kBlock, A.end - i0), ranges.data(),
            static_cast<int>(ranges.size()), self_range, xs_.data(), ys_.data(), zs_.data(), norm_.floor2,
            refined_estimate_, potential_.data(), fx_.data(), fy_.data(), fz_.data());
    }
    return sources * A.size();
  }

  CoulombEvaluation gather(bool want_potentials) {
    CoulombEvaluation result;
    result.summation_used = CoulombOptions::Summation::Fast;
    result.gradient.resize(n_, 3);
    if (want_potentials) result.potential.resize(n_);
    const double gradient_scale = -2 / (norm_.scale * norm_.scale);
    double energy = 0;
    for (Index s = 0; s < n_; ++s) energy += potential_[s];  // in Morton order, as always
#pragma omp parallel for schedule(static)
    for (Index s = 0; s < n_; ++s) {
      const Index i = order_[s];
      result.gradient(i, 0) = gradient_scale * fx_[s];
      result.gradient(i, 1) = gradient_scale * fy_[s];
      result.gradient(i, 2) = gradient_scale * fz_[s];
      if (want_potentials) result.potential[i] = potential_[s] / norm_.scale;
    }
    result.energy = energy / norm_.scale;
    return result;
  }

  const Points& X_;
  const Index n_;
  const MultiIndexTables& tables_;
  const int stride_;  // doubles per cell's expansion: count rounded up to a multiple of 4
  const std::vector<double> zero_moments_;  // the moments of an empty M2L lane
  const FmmParameters parameters_;
  const double theta_;
  const int leaf_size_;
  const bool framed_near_field_, refined_estimate_;
  CoulombFmmStats& stats_;
  const bool time_kernels_;
  coulomb_detail::NormalizedPoints norm_;
  Workspace& work_ = workspace();
  CoulombFmmTree* const tree_;  // kept between evaluations, or null
  const bool keep_;             // this evaluation keeps tree_'s cells and lists
  std::vector<int32_t>& order_;  // sorted position s holds input point order_[s]
  std::vector<uint64_t>& keys_ = work_.keys;  // the Morton keys of a built tree
  std::vector<double>&xd_ = work_.xd, &yd_ = work_.yd, &zd_ = work_.zd;
  // framed near field: float coordinates in each point's leaf frame
  std::vector<float>&xs_ = work_.xs, &ys_ = work_.ys, &zs_ = work_.zs;
  // otherwise: float high and low parts (coulomb_p2p.h)
  std::vector<float>&xf_ = work_.xf, &yf_ = work_.yf, &zf_ = work_.zf, &xl_ = work_.xl, &yl_ = work_.yl,
                    &zl_ = work_.zl;
  std::vector<Cell>& cells_;
  std::vector<int32_t>& depth_start_;  // cells of depth d: [depth_start_[d], depth_start_[d+1])
  std::vector<double>&multipoles_ = work_.multipoles, &locals_ = work_.locals;
  // Indexed by cell; only the first cells_.size() are this evaluation's (see run()).
  std::vector<std::vector<int32_t>>& m2l_lists_;
  std::vector<std::vector<int32_t>>& p2p_lists_;
  std::vector<std::vector<int32_t>>& deferred_ = work_.deferred;  // the lists' scratch (ListStorage)
  int32_t cut_ = 0;                        // find_subtrees()
  std::vector<int32_t> subtrees_, top_;  // find_subtrees()
  std::vector<double>&potential_ = work_.potential, &fx_ = work_.fx, &fy_ = work_.fy, &fz_ = work_.fz;
};

}  // namespace

CoulombEvaluation coulomb_fmm(const Points& X, const CoulombFmmOptions& options, CoulombFmmStats* stats,
                              CoulombFmmTree* tree) {
  const FmmParameters parameters = choose_parameters(options);
  CoulombFmmStats local_stats;
  CoulombFmmStats& s = stats ? *stats : local_stats;
  s = CoulombFmmStats{};
  s.order = parameters.order;
  s.opening_angle = parameters.opening_angle;
  s.leaf_size = parameters.leaf_size;
  CSHAPES_REQUIRE(X.allFinite(), "Coulomb FMM: the ", X.rows(), " points contain a non-finite coordinate");
  CSHAPES_REQUIRE(X.rows() < (Index(1) << 31) - kBlock, "Coulomb FMM: too many points (", X.rows(), ")");
  if (X.rows() == 0) {
    CoulombEvaluation empty;
    empty.summation_used = CoulombOptions::Summation::Fast;
    empty.gradient.resize(0, 3);
    if (options.want_potentials) empty.potential.resize(0);
    return empty;
  }
  Fmm fmm(X, parameters, options.min_distance, s, stats != nullptr, tree);
  return fmm.run(options.want_potentials);
}

}  // namespace cshapes
