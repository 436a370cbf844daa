#include "cshapes/matching/nearest_neighbors.h"

#include <omp.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <numeric>
#include <vector>

#include "cshapes/support/error.h"
#include "cshapes/support/simd.h"

namespace cshapes {

namespace {

// Points per leaf. A leaf's coordinates are kLeaf consecutive doubles per axis (structure of arrays), scanned
// a vector at a time (4 or 8 doubles, by instruction set) without a branch per point; splits put a multiple
// of kLeaf points on the left, so every leaf but the last is full. Large leaves suit ICP: a query lies off
// the other surface by about the RMSE, several point spacings, so its search ball meets many small cells and
// a deep tree costs a mispredicted branch per node: the time falls as the leaves grow, up to 64. Tried and
// dropped, both slower: a tight bounding box per leaf checked before its scan (one more unpredictable branch
// per leaf), and a single-precision first scan of each leaf with an exact rescan when it might hold a better
// point (most leaves a query meets need the rescan). The measurements: docs/design.md, "Measured figures
// behind choices in the code".
constexpr int kLeaf = 64;
static_assert(kLeaf % 32 == 0, "leaves are scanned 4 vectors of up to 8 at a time");

// One node of the tree, stored in depth-first order: an inner node's first child follows it.
struct Node {
  // Inner node: the points of the first child have coordinate `axis` ≤ low, those of the second child ≥ high
  // (low ≤ high: the largest and smallest coordinate on each side, so the gap between them prunes too).
  double low = 0, high = 0;
  int axis = -1;   // 0, 1, 2; −1 for a leaf
  int second = 0;  // inner node: index of the second child; leaf: its first slot (a multiple of kLeaf)
};

// What the search reads: the nodes, the leaves' coordinates (slot order), the bounding box of all points.
struct TreeArrays {
  const Node* nodes;
  const double *x, *y, *z;
  double box_low[3], box_high[3];
};
using FindFn = void (*)(const TreeArrays&, const double*, double&, int&);

// The search per instruction set (support/simd.h): vectors of 4 doubles in pairs of SSE2 registers or in
// AVX2's, of 8 in AVX-512's. The same bytes from each (nearest_neighbors_search.inl).
namespace baseline {
constexpr int kLanes = 4;
#include "cshapes/matching/nearest_neighbors_search.inl"
}  // namespace baseline

#pragma GCC push_options
#pragma GCC target("avx2")
namespace avx2 {
constexpr int kLanes = 4;
#include "cshapes/matching/nearest_neighbors_search.inl"
}  // namespace avx2
#pragma GCC pop_options

#pragma GCC push_options
#pragma GCC target("avx2,avx512f,avx512vl,avx512dq,avx512bw")
namespace avx512 {
constexpr int kLanes = 8;
#include "cshapes/matching/nearest_neighbors_search.inl"
}  // namespace avx512
#pragma GCC pop_options

FindFn find_for(SimdTarget target) {
  switch (target) {
    case SimdTarget::Avx512:
      return avx512::find_entry;
    case SimdTarget::Avx2:
      return avx2::find_entry;
    case SimdTarget::Baseline:
      break;
  }
  return baseline::find_entry;
}

}  // namespace

// A KD-tree in the manner of nanoflann's KDTreeSingleIndexAdaptor (split the widest side of the bounding
// box; search the nearer child first and the farther one only when the distance to its cell, updated one
// axis at a time (Arya & Mount 1993), is below the best distance), with the points copied into leaf order
// so a leaf is scanned without indirection. All arithmetic in double: results are exact (up to ties).
struct NearestNeighbors::Impl {
  Points points;
  std::vector<Node> nodes;
  // Slot s holds input row slot_index[s] at (x[s], y[s], z[s]); unused slots of the last leaf hold NaN
  // (never nearer than anything) and index −1.
  std::vector<double> x, y, z;
  std::vector<int> slot_index;
  std::vector<double> row_major;      // the points row after row: a hint's coordinates in one cache line
  Eigen::Vector3d box_low, box_high;  // bounding box of all points

  // A point while the tree is built (coordinates beside the row: the partitioning reads them in place).
  struct BuildItem {
    double xyz[3];
    int row;
  };
  // The search of this process's instruction set (support/simd.h), chosen when the tree is built.
  FindFn find_for_target = nullptr;
  int build(std::vector<BuildItem>& items, int begin, int end, int& next_slot);
  // Exact nearest slot to q among points nearer than sqrt(best_d2); best_slot unchanged if none.
  void find(const double* q, double& best_d2, int& best_slot) const;
};

namespace {

// Moves the items with coordinate `axis` below `pivot` (or ≤ it, when `or_equal`) to the front of
// [lo, hi), and returns where they end. Lomuto's scheme without a branch per item: swap, then advance
// the boundary by the comparison's outcome (a sorting network's mispredictions cost more than the swaps).
template <class Item>
int partition(std::vector<Item>& items, int lo, int hi, int axis, double pivot, bool or_equal) {
  int boundary = lo;
  for (int j = lo; j < hi; ++j) {
    const double v = items[static_cast<size_t>(j)].xyz[axis];  // read before the swap: no store to wait for
    std::swap(items[static_cast<size_t>(boundary)], items[static_cast<size_t>(j)]);
    boundary += or_equal ? (v <= pivot) : (v < pivot);
  }
  return boundary;
}

// As std::nth_element by coordinate `axis` (deterministic: same items, same result): the item of rank
// k − begin in [begin, end) at k, none after it smaller, none before it larger. Quickselect with the
// median of three as pivot.
template <class Item>
void select(std::vector<Item>& items, int begin, int end, int k, int axis) {
  int lo = begin, hi = end;
  while (hi - lo > 1) {
    double a = items[static_cast<size_t>(lo)].xyz[axis],
           b = items[static_cast<size_t>((lo + hi) / 2)].xyz[axis],
           c = items[static_cast<size_t>(hi - 1)].xyz[axis];
    const double pivot = std::max(std::min(a, b), std::min(std::max(a, b), c));
    const int smaller = partition(items, lo, hi, axis, pivot, false);
    if (k < smaller) {
      hi = smaller;
    } else if (smaller > lo) {
      lo = smaller;
    } else {  // the pivot is the least: split off the items equal to it (at least the pivot itself)
      const int equal = partition(items, lo, hi, axis, pivot, true);
      if (k < equal) return;
      lo = equal;
    }
  }
}

}  // namespace

int NearestNeighbors::Impl::build(std::vector<BuildItem>& items, int begin, int end, int& next_slot) {
  const int id = static_cast<int>(nodes.size());
  nodes.emplace_back();
  const int count = end - begin;
  if (count <= kLeaf) {
    Node& leaf = nodes[static_cast<size_t>(id)];
    leaf.second = next_slot;
    for (int k = 0; k < count; ++k) {
      const BuildItem& item = items[static_cast<size_t>(begin + k)];
      const size_t s = static_cast<size_t>(next_slot + k);
      x[s] = item.xyz[0];
      y[s] = item.xyz[1];
      z[s] = item.xyz[2];
      slot_index[s] = item.row;
    }
    next_slot += kLeaf;
    return id;
  }
  // Widest side of the points' bounding box.
  double lo[3], hi[3];
  for (int a = 0; a < 3; ++a) lo[a] = hi[a] = items[static_cast<size_t>(begin)].xyz[a];
  for (int k = begin + 1; k < end; ++k)
    for (int a = 0; a < 3; ++a) {
      lo[a] = std::min(lo[a], items[static_cast<size_t>(k)].xyz[a]);
      hi[a] = std::max(hi[a], items[static_cast<size_t>(k)].xyz[a]);
    }
  int axis = 0;
  for (int a = 1; a < 3; ++a)
    if (hi[a] - lo[a] > hi[axis] - lo[axis]) axis = a;
  // Near the median, rounded up to whole leaves (std::nth_element is deterministic: same points, same tree).
  const int half = (count / 2 + kLeaf - 1) / kLeaf * kLeaf;
  const int middle = begin + std::min(half, count - 1);
  select(items, begin, end, middle, axis);
  double low = -std::numeric_limits<double>::infinity();
  for (int k = begin; k < middle; ++k) low = std::max(low, items[static_cast<size_t>(k)].xyz[axis]);
  const double high = items[static_cast<size_t>(middle)].xyz[axis];
  build(items, begin, middle, next_slot);
  const int second = build(items, middle, end, next_slot);
  Node& inner = nodes[static_cast<size_t>(id)];
  inner.axis = axis;
  inner.low = low;
  inner.high = high;
  inner.second = second;
  return id;
}

void NearestNeighbors::Impl::find(const double* q, double& best_d2, int& best_slot) const {
  const TreeArrays t{nodes.data(), x.data(), y.data(), z.data(), {box_low[0], box_low[1], box_low[2]},
                     {box_high[0], box_high[1], box_high[2]}};
  find_for_target(t, q, best_d2, best_slot);
}

NearestNeighbors::NearestNeighbors(const Points& points) : impl_(std::make_unique<Impl>()) {
  CSHAPES_REQUIRE(points.rows() > 0, "nearest neighbours: the point set is empty");
  CSHAPES_REQUIRE(points.allFinite(), "nearest neighbours: the point set has non-finite coordinates");
  CSHAPES_REQUIRE(points.rows() < (Index(1) << 28), "nearest neighbours: too many points (", points.rows(),
                  ")");
  Impl& t = *impl_;
  t.points = points;
  t.row_major.resize(static_cast<size_t>(3 * points.rows()));
  Eigen::Map<Eigen::Matrix<double, Eigen::Dynamic, 3, Eigen::RowMajor>>(t.row_major.data(), points.rows(),
                                                                        3) = points;
  const int n = static_cast<int>(points.rows());
  const size_t slots = static_cast<size_t>((n + kLeaf - 1) / kLeaf * kLeaf);
  t.x.assign(slots, std::numeric_limits<double>::quiet_NaN());
  t.y = t.x;
  t.z = t.x;
  t.slot_index.assign(slots, -1);
  t.nodes.reserve(static_cast<size_t>(2 * n / kLeaf + 2));
  std::vector<Impl::BuildItem> items(static_cast<size_t>(n));
  for (int i = 0; i < n; ++i) items[static_cast<size_t>(i)] = {{points(i, 0), points(i, 1), points(i, 2)}, i};
  int next_slot = 0;
  t.build(items, 0, n, next_slot);
  t.box_low = points.colwise().minCoeff().transpose();
  t.box_high = points.colwise().maxCoeff().transpose();
  t.find_for_target = find_for(simd_target());
}

NearestNeighbors::~NearestNeighbors() = default;
NearestNeighbors::NearestNeighbors(NearestNeighbors&&) noexcept = default;
NearestNeighbors& NearestNeighbors::operator=(NearestNeighbors&&) noexcept = default;

Index NearestNeighbors::size() const {
  return impl_->points.rows();
}
const Points& NearestNeighbors::points() const {
  return impl_->points;
}

Index NearestNeighbors::nearest(const Eigen::Vector3d& q, double* squared_distance) const {
  double best_d2 = std::numeric_limits<double>::infinity();
  int best_slot = -1;
  impl_->find(q.data(), best_d2, best_slot);
  if (squared_distance) *squared_distance = best_d2;
  return impl_->slot_index[static_cast<size_t>(best_slot)];
}

Index NearestNeighbors::nearest(const Eigen::Vector3d& q, Index hint, double* squared_distance) const {
  const double* h = &impl_->row_major[static_cast<size_t>(3 * hint)];
  const double dx = h[0] - q[0], dy = h[1] - q[1], dz = h[2] - q[2];
  const double hint_d2 = dx * dx + dy * dy + dz * dz;
  // Strict '<' in the search: inflate the bound a little so that the hint itself (or a tie) qualifies.
  double best_d2 = hint_d2 * (1 + 1e-12) + 1e-300;
  int best_slot = -1;
  impl_->find(q.data(), best_d2, best_slot);
  Index best = best_slot >= 0 ? impl_->slot_index[static_cast<size_t>(best_slot)] : hint;
  if (best_slot < 0 || best_d2 > hint_d2) {
    best = hint;
    best_d2 = hint_d2;
  }
  if (squared_distance) *squared_distance = best_d2;
  return best;
}

void NearestNeighbors::nearest_all(const Points& queries, Eigen::VectorXi& index,
                                   Eigen::VectorXd& squared_distance, bool parallel) const {
  const Index m = queries.rows();
  index.resize(m);
  squared_distance.resize(m);
#pragma omp parallel for schedule(static) if (parallel && !omp_in_parallel() && m > 2000)
  for (Index i = 0; i < m; ++i) {
    Eigen::Vector3d q = queries.row(i).transpose();
    double d2 = 0;
    index[i] = static_cast<int>(nearest(q, &d2));
    squared_distance[i] = d2;
  }
}

}  // namespace cshapes
