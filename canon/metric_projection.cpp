#include "cshapes/canon/metric_projection.h"

#include <immintrin.h>

#include <algorithm>
#include <cmath>
#include <numeric>
#include <vector>

#include "cshapes/support/error.h"
#include "cshapes/support/simd.h"

namespace cshapes {

ProjectionNorm parse_projection_norm(const std::string& name) {
  if (name == "l2") return ProjectionNorm::L2;
  if (name == "l1") return ProjectionNorm::L1;
  fail("unknown projection norm '", name, "'; known: l2, l1");
}

std::string to_string(ProjectionNorm norm) {
  return norm == ProjectionNorm::L2 ? "l2" : "l1";
}

namespace {

// Edges per block of the edge pass (a multiple of 4, the vector width).
constexpr Index kEdgeBlock = 256;
// Vertices per block of the vertex pass and the copies in and out.
constexpr Index kVertexBlock = 256;
// Below this many vertices the sweeps run on one thread: a projection is then too short to pay for two
// barriers per sweep. Above it two threads are faster when the cores are free; a barrier waits for a thread
// the OS may have descheduled, so a busy core slows single projections, though not whole runs (the
// measurements: docs/design.md, "Measured figures behind choices in the code").
constexpr Index kParallelMinVertices = 2000;
// Edges per block of the violation's partial sums (violation_block's buffer holds this many).
constexpr int kViolationBlock = 1024;

}  // namespace

MetricProjection::MetricProjection(Index num_vertices, const Edges& E, const Eigen::VectorXd& rest_lengths,
                                   const MetricProjectionOptions& options)
    : n_(num_vertices), options_(options) {
  CSHAPES_REQUIRE(num_vertices >= 0, "metric projection: ", num_vertices, " vertices");
  CSHAPES_REQUIRE(rest_lengths.size() == E.rows(), "metric projection: ", rest_lengths.size(),
                  " rest lengths for ", E.rows(), " edges");
  check_limit(projection_limits::kSteps, options.steps, "metric projection");
  check_limit(projection_limits::kDilation, options.dilation, "metric projection");
  check_limit(projection_limits::kL1Floor, options.l1_floor, "metric projection");
  for (Index e = 0; e < E.rows(); ++e) {
    CSHAPES_REQUIRE(E(e, 0) >= 0 && E(e, 0) < n_ && E(e, 1) >= 0 && E(e, 1) < n_ && E(e, 0) != E(e, 1),
                    "metric projection: edge ", e, " (", E(e, 0), ", ", E(e, 1),
                    ") is not a pair of distinct "
                    "vertices in [0, ",
                    n_, ")");
    CSHAPES_REQUIRE(std::isfinite(rest_lengths(e)) && rest_lengths(e) >= 0,
                    "metric projection: rest length of edge ", e, " is ", rest_lengths(e),
                    ", expected a finite value >= 0");
  }
  // Zero rest lengths (duplicate points of a point cloud) are raised to a tiny fraction of the largest, so
  // the relative floors and violations below stay finite.
  const double tiny = 1e-12 * (rest_lengths.size() ? std::max(rest_lengths.maxCoeff(), 1e-300) : 1.0);

  // Internal vertex order: breadth-first over the graph, so that the neighbours of a vertex lie close to it
  // in memory whatever the input order (remeshed or shuffled meshes have none: michael22738's neighbours are
  // ~8,000 indices apart). The sweep's arithmetic does not depend on it, only its speed.
  const Index m = E.rows();
  const Adjacency adj = adjacency(n_, E);
  order_.clear();
  order_.reserve(n_);
  std::vector<int> rank(n_, -1);
  for (Index start = 0; start < n_; ++start) {
    if (rank[start] >= 0) continue;
    rank[start] = static_cast<int>(order_.size());
    order_.push_back(static_cast<int>(start));
    for (size_t head = order_.size() - 1; head < order_.size(); ++head) {
      const int v = order_[head];
      for (int k = adj.offsets[v]; k < adj.offsets[v + 1]; ++k) {
        const int w = adj.neighbors[k];
        if (rank[w] >= 0) continue;
        rank[w] = static_cast<int>(order_.size());
        order_.push_back(w);
      }
    }
  }
  // Orient every edge a < b (internal indices) and sort by (a, b); the sort is stable, so repeated edges keep
  // their input order.
  std::vector<Index> order(m);
  std::iota(order.begin(), order.end(), Index(0));
  auto lo = [&](Index e) { return std::min(rank[E(e, 0)], rank[E(e, 1)]); };
  auto hi = [&](Index e) { return std::max(rank[E(e, 0)], rank[E(e, 1)]); };
  std::stable_sort(order.begin(), order.end(),
                   [&](Index p, Index q) { return lo(p) != lo(q) ? lo(p) < lo(q) : hi(p) < hi(q); });
  edge_a_.resize(m);
  edge_b_.resize(m);
  edge_rest_.resize(m);
  // Slots: vertex i owns slots [offsets_[i], offsets_[i+1]), one per edge, ordered by neighbour index — the
  // edges (a, i), a < i, by a (the sorted order), then the edges (i, b), b > i, by b.
  offsets_.assign(n_ + 1, 0);
  for (Index k = 0; k < m; ++k) {
    edge_a_[k] = lo(order[k]);
    edge_b_[k] = hi(order[k]);
    edge_rest_[k] = std::max(rest_lengths(order[k]), tiny);
    ++offsets_[edge_a_[k] + 1];
    ++offsets_[edge_b_[k] + 1];
  }
  for (Index i = 0; i < n_; ++i) offsets_[i + 1] += offsets_[i];
  slot_a_.resize(m);
  slot_b_.resize(m);
  std::vector<int> fill(offsets_.begin(), offsets_.end() - 1);
  for (Index k = 0; k < m; ++k) slot_b_[k] = fill[edge_b_[k]]++;  // a < b: these come first at b
  for (Index k = 0; k < m; ++k) slot_a_[k] = fill[edge_a_[k]]++;
  inverse_degree_.resize(n_);
  for (Index i = 0; i < n_; ++i) {
    const int degree = offsets_[i + 1] - offsets_[i];
    inverse_degree_[i] = degree > 0 ? 1.0 / degree : 0.0;
  }
}

void MetricProjection::sweep(Points& X) const {
  sweeps(X, 1, nullptr);
}

void MetricProjection::project(Points& X, RelativeViolation* violation) const {
  sweeps(X, options_.steps, violation);
}

namespace {

struct EdgeParameters {
  double dilation, inv_dilation, floor;
};

// One edge (a, b), a < b, of the sweep: the projections of x_a onto the sphere of radius t about x_b and of
// x_b onto the sphere about x_a, x_b + (t/r)(x_a − x_b) and x_a − (t/r)(x_a − x_b), times the weight w, into
// the records to_a and to_b (fourth lane: w). pa, pb: (x, y, z, 1) records.
template <bool L1, bool Dilation>
inline void project_edge(const double* pa, const double* pb, double d, const EdgeParameters& p, double* to_a,
                         double* to_b) {
  const double ux = pa[0] - pb[0], uy = pa[1] - pb[1], uz = pa[2] - pb[2];
  const double r = std::sqrt(ux * ux + uy * uy + uz * uz);
  // eq. (3): the target is the length itself when it lies in the band, so such an edge does not pull.
  const double target = Dilation ? std::min(std::max(r, d * p.inv_dilation), d * p.dilation) : d;
  // eq. (9): weights ~ 1/|r_ij − d_ij|, floored relative to d_ij (see the header).
  const double w = L1 ? 1.0 / std::max(std::abs(r - d), p.floor * d) : 1.0;
  double vx, vy, vz;
  if (r > 1e-12 * d) {
    const double scale = target / r;
    vx = scale * ux;
    vy = scale * uy;
    vz = scale * uz;
  } else {  // coincident endpoints (or NaN): a fixed direction, +e_x from b to a, so they separate
    vx = target;
    vy = 0;
    vz = 0;
  }
  to_a[0] = w * (pb[0] + vx);
  to_a[1] = w * (pb[1] + vy);
  to_a[2] = w * (pb[2] + vz);
  to_a[3] = w;
  to_b[0] = w * (pa[0] - vx);
  to_b[1] = w * (pa[1] - vy);
  to_b[2] = w * (pa[2] - vz);
  to_b[3] = w;
}

#pragma GCC push_options
#pragma GCC target("avx2,fma")
namespace avx2 {
#include "cshapes/canon/metric_projection_simd.inl"
}  // namespace avx2
#pragma GCC pop_options

#pragma GCC push_options
#pragma GCC target("avx2,fma,avx512f,avx512vl,avx512dq,avx512bw")
namespace avx512 {
#include "cshapes/canon/metric_projection_simd.inl"
}  // namespace avx512
#pragma GCC pop_options

}  // namespace

// Pass 1 of a sweep, edges [first, last): the weighted projections of both endpoints, into their slots.
// `positions` holds (x, y, z, 1) records.
template <bool L1, bool Dilation>
void MetricProjection::edge_pass(const double* positions, Index first, Index last) const {
  const EdgeParameters p{options_.dilation, 1.0 / options_.dilation, options_.l1_floor};
  const int* a = edge_a_.data();
  const int* b = edge_b_.data();
  const int* slot_a = slot_a_.data();
  const int* slot_b = slot_b_.data();
  const double* rest = edge_rest_.data();
  double* slots = slots_.data();
  const SimdTarget target = simd_target();
  Index e = first;
  if (target == SimdTarget::Avx512)
    e = avx512::edge_pass_vector<L1, Dilation>(positions, a, b, slot_a, slot_b, rest, slots, e, last, p);
  else if (target == SimdTarget::Avx2)
    e = avx2::edge_pass_vector<L1, Dilation>(positions, a, b, slot_a, slot_b, rest, slots, e, last, p);
  for (; e < last; ++e)
    project_edge<L1, Dilation>(positions + 4 * Index(a[e]), positions + 4 * Index(b[e]), rest[e], p,
                               slots + 4 * Index(slot_a[e]), slots + 4 * Index(slot_b[e]));
}

// Pass 2 of a sweep, vertices [first, last): eq. (6) / eq. (8), the weighted mean of the projections in the
// vertex's slots, into `out` (the fourth lane of the slots sums the weights).
template <bool L1>
void MetricProjection::vertex_pass(const double* positions, double* out, Index first, Index last) const {
  const double* slots = slots_.data();
  const double* inverse_degree = inverse_degree_.data();
  const SimdTarget target = simd_target();
  if (target == SimdTarget::Avx512)
    return avx512::vertex_pass_vector<L1>(positions, out, slots, inverse_degree, offsets_.data(), first,
                                          last);
  if (target == SimdTarget::Avx2)
    return avx2::vertex_pass_vector<L1>(positions, out, slots, inverse_degree, offsets_.data(), first, last);
  for (Index i = first; i < last; ++i) {
    const int begin = offsets_[i], end = offsets_[i + 1];
    double sum[4] = {0, 0, 0, 0};
    for (int k = begin; k < end; ++k)
      for (int c = 0; c < 4; ++c) sum[c] += slots[4 * Index(k) + c];
    double* o = out + 4 * i;
    if (begin == end) {  // an isolated vertex stays where it is
      for (int c = 0; c < 4; ++c) o[c] = positions[4 * i + c];
    } else if constexpr (L1) {  // eq. (8): a division, as the vector pass divides; the fourth lane 1 again
      for (int c = 0; c < 3; ++c) o[c] = sum[c] / sum[3];
      o[3] = 1;
    } else {  // eq. (6): times 1/v_i; the fourth lane 1 again
      for (int c = 0; c < 3; ++c) o[c] = sum[c] * inverse_degree[i];
      o[3] = 1;
    }
  }
}

namespace {

// Partial sums of |r − d| / d over edges [first, last) of the (a, b) lists, with r² from `length2` (a functor
// (a, b) → ‖x_a − x_b‖²): the sum (four interleaved lanes in a fixed pattern, so not one long chain of
// dependent additions) and the max.
template <class Length2>
void violation_block(const int* a, const int* b, const double* rest, Index first, Index last, Length2 length2,
                     double* sum, double* max) {
  alignas(32) double relative[kViolationBlock];
  const int count = static_cast<int>(last - first);
  for (int k = 0; k < count; ++k) relative[k] = length2(a[first + k], b[first + k]);
  const double* d = rest + first;
  // Square roots and divisions in a loop of their own, so they vectorise.
  for (int k = 0; k < count; ++k) relative[k] = std::abs(std::sqrt(relative[k]) - d[k]) / d[k];
  double lanes[4] = {0, 0, 0, 0}, lane_max[4] = {0, 0, 0, 0};
  int k = 0;
  for (; k + 4 <= count; k += 4)
    for (int c = 0; c < 4; ++c) {
      lanes[c] += relative[k + c];
      lane_max[c] = std::max(lane_max[c], relative[k + c]);
    }
  for (; k < count; ++k) {
    lanes[0] += relative[k];
    lane_max[0] = std::max(lane_max[0], relative[k]);
  }
  *sum = (lanes[0] + lanes[1]) + (lanes[2] + lanes[3]);
  *max = std::max(std::max(lane_max[0], lane_max[1]), std::max(lane_max[2], lane_max[3]));
}

}  // namespace

RelativeViolation MetricProjection::combine_violation_blocks() const {
  RelativeViolation v;
  double total = 0;
  for (size_t block = 0; block < block_sums_.size(); ++block) {  // in block order: thread-count independent
    total += block_sums_[block];
    v.max = std::max(v.max, block_maxima_[block]);
  }
  v.mean = num_edges() ? total / static_cast<double>(num_edges()) : 0.0;
  return v;
}

void MetricProjection::sweeps(Points& X, int count, RelativeViolation* violation) const {
  CSHAPES_REQUIRE(X.rows() == n_, "metric projection: X has ", X.rows(), " rows, expected ", n_);
  if (count <= 0 || n_ == 0) {
    if (violation) *violation = relative_violation(X);
    return;
  }
  const Index m = num_edges();
  positions_a_.resize(4 * n_);
  positions_b_.resize(4 * n_);
  slots_.resize(8 * m);
  const Index violation_blocks = violation ? (m + kViolationBlock - 1) / kViolationBlock : 0;
  block_sums_.resize(violation_blocks);
  block_maxima_.resize(violation_blocks);
  const bool l1 = options_.norm == ProjectionNorm::L1, dilation = options_.dilation > 1;
  const Index edge_blocks = (m + kEdgeBlock - 1) / kEdgeBlock;
  const Index vertex_blocks = (n_ + kVertexBlock - 1) / kVertexBlock;
  double* x = X.data();  // column-major n×3
  const int* order = order_.data();
  double* buffers[2] = {positions_a_.data(), positions_b_.data()};
#pragma omp parallel if (n_ >= kParallelMinVertices)
  {
#pragma omp for schedule(static)
    for (Index block = 0; block < vertex_blocks; ++block)
      for (Index i = block * kVertexBlock; i < std::min(n_, (block + 1) * kVertexBlock); ++i) {
        double* p = buffers[0] + 4 * i;
        const Index row = order[i];
        p[0] = x[row];
        p[1] = x[n_ + row];
        p[2] = x[2 * n_ + row];
        p[3] = 1;
      }
    for (int step = 0; step < count; ++step) {
      const double* in = buffers[step % 2];
      double* out = buffers[(step + 1) % 2];
#pragma omp for schedule(static)
      for (Index block = 0; block < edge_blocks; ++block) {
        const Index first = block * kEdgeBlock, last = std::min(m, first + kEdgeBlock);
        if (l1) {
          if (dilation)
            edge_pass<true, true>(in, first, last);
          else
            edge_pass<true, false>(in, first, last);
        } else {
          if (dilation)
            edge_pass<false, true>(in, first, last);
          else
            edge_pass<false, false>(in, first, last);
        }
      }
#pragma omp for schedule(static)
      for (Index block = 0; block < vertex_blocks; ++block) {
        const Index first = block * kVertexBlock, last = std::min(n_, first + kVertexBlock);
        if (l1)
          vertex_pass<true>(in, out, first, last);
        else
          vertex_pass<false>(in, out, first, last);
      }
    }
    const double* result = buffers[count % 2];
    // The violation of the result, from the records while they are in cache (no barrier needed before the
    // copy-out below: both only read `result`).
#pragma omp for schedule(static) nowait
    for (Index block = 0; block < violation_blocks; ++block) {
      const Index first = block * kViolationBlock, last = std::min(m, first + kViolationBlock);
      violation_block(
          edge_a_.data(), edge_b_.data(), edge_rest_.data(), first, last,
          [&](int a, int b) {
            const double* pa = result + 4 * Index(a);
            const double* pb = result + 4 * Index(b);
            const double dx = pa[0] - pb[0], dy = pa[1] - pb[1], dz = pa[2] - pb[2];
            return dx * dx + dy * dy + dz * dz;
          },
          &block_sums_[block], &block_maxima_[block]);
    }
#pragma omp for schedule(static)
    for (Index block = 0; block < vertex_blocks; ++block)
      for (Index i = block * kVertexBlock; i < std::min(n_, (block + 1) * kVertexBlock); ++i) {
        const double* p = result + 4 * i;
        const Index row = order[i];
        x[row] = p[0];
        x[n_ + row] = p[1];
        x[2 * n_ + row] = p[2];
      }
  }
  if (violation) *violation = combine_violation_blocks();
}

RelativeViolation MetricProjection::relative_violation(const Points& X) const {
  CSHAPES_REQUIRE(X.rows() == n_, "metric projection: X has ", X.rows(), " rows, expected ", n_);
  const Index m = num_edges();
  const double* x = X.data();
  const double* y = x + n_;
  const double* z = y + n_;
  const int* order = order_.data();
  const Index blocks = (m + kViolationBlock - 1) / kViolationBlock;
  block_sums_.resize(blocks);
  block_maxima_.resize(blocks);
#pragma omp parallel for schedule(static) if (n_ >= kParallelMinVertices)
  for (Index block = 0; block < blocks; ++block) {
    const Index first = block * kViolationBlock, last = std::min(m, first + kViolationBlock);
    violation_block(
        edge_a_.data(), edge_b_.data(), edge_rest_.data(), first, last,
        [&](int a, int b) {
          const Index ra = order[a], rb = order[b];
          const double dx = x[ra] - x[rb], dy = y[ra] - y[rb], dz = z[ra] - z[rb];
          return dx * dx + dy * dy + dz * dz;
        },
        &block_sums_[block], &block_maxima_[block]);
  }
  return combine_violation_blocks();
}

MetricViolation metric_violation(const Points& X, const Edges& E, const Eigen::VectorXd& rest_lengths) {
  CSHAPES_REQUIRE(rest_lengths.size() == E.rows(), "metric violation: ", rest_lengths.size(),
                  " rest lengths for ", E.rows(), " edges");
  MetricViolation v;
  if (E.rows() == 0) return v;
  std::vector<double> ratio(E.rows());
  double sum_relative = 0;
  for (Index e = 0; e < E.rows(); ++e) {
    const double r = (X.row(E(e, 0)) - X.row(E(e, 1))).norm();
    const double d = rest_lengths(e);
    const double dev = std::abs(r - d);
    v.residual += dev * dev;
    v.l1 += dev;
    const double rel = d > 0 ? dev / d : (dev > 0 ? INFINITY : 0.0);
    sum_relative += rel;
    v.max_relative = std::max(v.max_relative, rel);
    ratio[e] = d > 0 ? r / d : 1.0;
  }
  v.mean_relative = sum_relative / E.rows();
  auto mid = ratio.begin() + ratio.size() / 2;
  std::nth_element(ratio.begin(), mid, ratio.end());
  v.median_length_ratio = *mid;
  return v;
}

}  // namespace cshapes
