#include "canon/metric_projection.h"

#include <algorithm>
#if defined(__AVX2__) && defined(__FMA__)
#include <immintrin.h>
#endif
#include <cmath>
#include <numeric>
#include <vector>

#include "core/error.h"

namespace cshapes {

ProjectionNorm parse_projection_norm(const std::string& name) {
  if (name == "l2") return ProjectionNorm::L2;
  if (name == "l1") return ProjectionNorm::L1;
  fail("unknown projection norm '", name, "'; known: l2, l1");
}

std::string to_string(ProjectionNorm norm) { return norm == ProjectionNorm::L2 ? "l2" : "l1"; }

namespace {

// Edges per block of the edge pass (a multiple of 4, the vector width).
constexpr Index kEdgeBlock = 256;
// Vertices per block of the vertex pass and the copies in and out.
constexpr Index kVertexBlock = 256;
// Below this many vertices a sweep runs on one thread: forking and the two barriers per sweep cost more than
// they save (measured on 2 cores: at 5,000 vertices two threads take 0.55× the time of one).
constexpr Index kParallelMinVertices = 2000;
// Edges per block of relative_violation's sums.
constexpr Index kViolationBlock = 1024;

}  // namespace

MetricProjection::MetricProjection(Index num_vertices, const Edges& E, const Eigen::VectorXd& rest_lengths,
                                   const MetricProjectionOptions& options)
    : n_(num_vertices), options_(options) {
  CSHAPES_REQUIRE(num_vertices >= 0, "metric projection: ", num_vertices, " vertices");
  CSHAPES_REQUIRE(rest_lengths.size() == E.rows(), "metric projection: ", rest_lengths.size(),
                  " rest lengths for ", E.rows(), " edges");
  CSHAPES_REQUIRE(options.steps >= 0, "metric projection: steps must be >= 0, got ", options.steps);
  CSHAPES_REQUIRE(options.dilation >= 1, "metric projection: dilation must be >= 1, got ", options.dilation);
  CSHAPES_REQUIRE(options.l1_floor > 0, "metric projection: l1_floor must be > 0, got ", options.l1_floor);
  for (Index e = 0; e < E.rows(); ++e) {
    CSHAPES_REQUIRE(E(e, 0) >= 0 && E(e, 0) < n_ && E(e, 1) >= 0 && E(e, 1) < n_ && E(e, 0) != E(e, 1),
                    "metric projection: edge ", e, " (", E(e, 0), ", ", E(e, 1), ") is not a pair of distinct "
                    "vertices in [0, ", n_, ")");
    CSHAPES_REQUIRE(std::isfinite(rest_lengths(e)) && rest_lengths(e) >= 0, "metric projection: rest length of edge ",
                    e, " is ", rest_lengths(e), ", expected a finite value >= 0");
  }
  // Zero rest lengths (duplicate points of a point cloud) are raised to a tiny fraction of the largest, so the
  // relative floors and violations below stay finite.
  const double tiny = 1e-12 * (rest_lengths.size() ? std::max(rest_lengths.maxCoeff(), 1e-300) : 1.0);

  // Orient every edge a < b and sort by (a, b); the sort is stable, so repeated edges keep their input order.
  const Index m = E.rows();
  std::vector<Index> order(m);
  std::iota(order.begin(), order.end(), Index(0));
  auto lo = [&](Index e) { return std::min(E(e, 0), E(e, 1)); };
  auto hi = [&](Index e) { return std::max(E(e, 0), E(e, 1)); };
  std::stable_sort(order.begin(), order.end(),
                   [&](Index p, Index q) { return lo(p) != lo(q) ? lo(p) < lo(q) : hi(p) < hi(q); });
  edge_a_.resize(m);
  edge_b_.resize(m);
  edge_rest_.resize(m);
  upper_offsets_.assign(n_ + 1, 0);
  lower_offsets_.assign(n_ + 1, 0);
  for (Index k = 0; k < m; ++k) {
    const Index e = order[k];
    edge_a_[k] = lo(e);
    edge_b_[k] = hi(e);
    edge_rest_[k] = std::max(rest_lengths(e), tiny);
    ++upper_offsets_[edge_a_[k] + 1];
    ++lower_offsets_[edge_b_[k] + 1];
  }
  for (Index i = 0; i < n_; ++i) {
    upper_offsets_[i + 1] += upper_offsets_[i];
    lower_offsets_[i + 1] += lower_offsets_[i];
  }
  // Edges (a, i) listed per i; scanning the edges in (a, b) order leaves each list sorted by a.
  lower_edges_.resize(m);
  std::vector<int> fill(lower_offsets_.begin(), lower_offsets_.end() - 1);
  for (Index k = 0; k < m; ++k) lower_edges_[fill[edge_b_[k]]++] = static_cast<int>(k);
  inverse_degree_.resize(n_);
  for (Index i = 0; i < n_; ++i) {
    const int degree = upper_offsets_[i + 1] - upper_offsets_[i] + lower_offsets_[i + 1] - lower_offsets_[i];
    inverse_degree_[i] = degree > 0 ? 1.0 / degree : 0.0;
  }
}

void MetricProjection::sweep(Points& X) const { sweeps(X, 1); }

void MetricProjection::project(Points& X) const { sweeps(X, options_.steps); }

namespace {

struct EdgeParameters {
  double dilation, inv_dilation, floor;
};

// The correction of one edge (a, b), a < b: v = w · t · (x_a − x_b) / ‖x_a − x_b‖ into v[0..3] (v[3] = 0),
// and the weight w. pa, pb: (x, y, z, 1) records.
template <bool L1, bool Dilation>
inline void edge_correction(const double* pa, const double* pb, double d, const EdgeParameters& p, double* v,
                            double* weight) {
  const double ux = pa[0] - pb[0], uy = pa[1] - pb[1], uz = pa[2] - pb[2];
  const double r = std::sqrt(ux * ux + uy * uy + uz * uz);
  // eq. (3): the target is the length itself when it lies in the band, so such an edge does not pull.
  const double target = Dilation ? std::min(std::max(r, d * p.inv_dilation), d * p.dilation) : d;
  // eq. (9): weights ~ 1/|r_ij − d_ij|, floored relative to d_ij (see the header).
  const double w = L1 ? 1.0 / std::max(std::abs(r - d), p.floor * d) : 1.0;
  if (L1) *weight = w;
  if (r > 1e-12 * d) {
    const double factor = w * target / r;
    v[0] = factor * ux;
    v[1] = factor * uy;
    v[2] = factor * uz;
  } else {  // coincident endpoints (or NaN): a fixed direction, +e_x from b to a, so they separate
    v[0] = w * target;
    v[1] = 0;
    v[2] = 0;
  }
  v[3] = 0;
}

}  // namespace

// Pass 1 of a sweep, edges [first, last): the corrections v_ab (with the weight folded in) and, for L1, the
// weights. `positions` holds (x, y, z, 1) records.
template <bool L1, bool Dilation>
void MetricProjection::edge_pass(const double* positions, Index first, Index last) const {
  const EdgeParameters p{options_.dilation, 1.0 / options_.dilation, options_.l1_floor};
  const int* a = edge_a_.data();
  const int* b = edge_b_.data();
  const double* rest = edge_rest_.data();
  double* corrections = corrections_.data();
  double* weights = weights_.data();
  Index e = first;
#if defined(__AVX2__) && defined(__FMA__)
  // Four edges at a time: the square roots and divisions, the bulk of the cost, run four-wide.
  const __m256d one = _mm256_set1_pd(1.0), tiny = _mm256_set1_pd(1e-12);
  for (; e + 4 <= last; e += 4) {
    const __m256d u0 = _mm256_sub_pd(_mm256_load_pd(positions + 4 * Index(a[e])),
                                     _mm256_load_pd(positions + 4 * Index(b[e])));
    const __m256d u1 = _mm256_sub_pd(_mm256_load_pd(positions + 4 * Index(a[e + 1])),
                                     _mm256_load_pd(positions + 4 * Index(b[e + 1])));
    const __m256d u2 = _mm256_sub_pd(_mm256_load_pd(positions + 4 * Index(a[e + 2])),
                                     _mm256_load_pd(positions + 4 * Index(b[e + 2])));
    const __m256d u3 = _mm256_sub_pd(_mm256_load_pd(positions + 4 * Index(a[e + 3])),
                                     _mm256_load_pd(positions + 4 * Index(b[e + 3])));
    // Squared lengths of the four edges in one vector (the fourth lanes of u are 0).
    const __m256d h01 = _mm256_hadd_pd(_mm256_mul_pd(u0, u0), _mm256_mul_pd(u1, u1));
    const __m256d h23 = _mm256_hadd_pd(_mm256_mul_pd(u2, u2), _mm256_mul_pd(u3, u3));
    const __m256d length2 =
        _mm256_add_pd(_mm256_permute2f128_pd(h01, h23, 0x20), _mm256_permute2f128_pd(h01, h23, 0x31));
    const __m256d r = _mm256_sqrt_pd(length2);
    const __m256d d = _mm256_loadu_pd(rest + e);
    __m256d target = d;
    if constexpr (Dilation)
      target = _mm256_min_pd(_mm256_max_pd(r, _mm256_mul_pd(d, _mm256_set1_pd(p.inv_dilation))),
                             _mm256_mul_pd(d, _mm256_set1_pd(p.dilation)));
    if constexpr (L1) {
      const __m256d deviation = _mm256_andnot_pd(_mm256_set1_pd(-0.0), _mm256_sub_pd(r, d));
      const __m256d w = _mm256_div_pd(one, _mm256_max_pd(deviation, _mm256_mul_pd(d, _mm256_set1_pd(p.floor))));
      _mm256_storeu_pd(weights + e, w);
      target = _mm256_mul_pd(w, target);  // w·t
    }
    const __m256d apart = _mm256_cmp_pd(r, _mm256_mul_pd(tiny, d), _CMP_GT_OQ);
    // w·t / r where the endpoints are apart, 0 where they coincide (divided by 1 there: no infinities).
    const __m256d factor = _mm256_and_pd(apart, _mm256_div_pd(target, _mm256_blendv_pd(one, r, apart)));
    double* v = corrections + 4 * e;
    _mm256_store_pd(v, _mm256_mul_pd(u0, _mm256_permute4x64_pd(factor, 0x00)));
    _mm256_store_pd(v + 4, _mm256_mul_pd(u1, _mm256_permute4x64_pd(factor, 0x55)));
    _mm256_store_pd(v + 8, _mm256_mul_pd(u2, _mm256_permute4x64_pd(factor, 0xAA)));
    _mm256_store_pd(v + 12, _mm256_mul_pd(u3, _mm256_permute4x64_pd(factor, 0xFF)));
    const int apart_mask = _mm256_movemask_pd(apart);
    if (apart_mask != 0xF)  // rare: coincident endpoints, done one by one
      for (int k = 0; k < 4; ++k)
        if (!(apart_mask & (1 << k)))
          edge_correction<L1, Dilation>(positions + 4 * Index(a[e + k]), positions + 4 * Index(b[e + k]),
                                        rest[e + k], p, v + 4 * k, weights + e + k);
  }
#endif
  for (; e < last; ++e)
    edge_correction<L1, Dilation>(positions + 4 * Index(a[e]), positions + 4 * Index(b[e]), rest[e], p,
                                  corrections + 4 * e, weights + e);
}

// Pass 2 of a sweep, vertices [first, last): eq. (6) / eq. (8), the weighted mean of the projections
// x_j ± v_ij, into `out`. The fourth lane of the records sums the weights (positions carry a 1 there).
template <bool L1>
void MetricProjection::vertex_pass(const double* positions, double* out, Index first, Index last) const {
  const double* corrections = corrections_.data();
  const double* weights = weights_.data();
  const double* inverse_degree = inverse_degree_.data();
  for (Index i = first; i < last; ++i) {
#if defined(__AVX2__) && defined(__FMA__)
    __m256d sum = _mm256_setzero_pd();
    for (int k = lower_offsets_[i]; k < lower_offsets_[i + 1]; ++k) {  // edges (j, i), j < i: x_j − v
      const Index e = lower_edges_[k];
      const __m256d pj = _mm256_load_pd(positions + 4 * Index(edge_a_[e]));
      const __m256d v = _mm256_load_pd(corrections + 4 * e);
      sum = _mm256_add_pd(sum, L1 ? _mm256_fmsub_pd(_mm256_broadcast_sd(weights + e), pj, v) : _mm256_sub_pd(pj, v));
    }
    for (Index e = upper_offsets_[i]; e < upper_offsets_[i + 1]; ++e) {  // edges (i, j), j > i: x_j + v
      const __m256d pj = _mm256_load_pd(positions + 4 * Index(edge_b_[e]));
      const __m256d v = _mm256_load_pd(corrections + 4 * e);
      sum = _mm256_add_pd(sum, L1 ? _mm256_fmadd_pd(_mm256_broadcast_sd(weights + e), pj, v) : _mm256_add_pd(pj, v));
    }
    const __m256d weight_sum = _mm256_permute4x64_pd(sum, 0xFF);
    __m256d result;
    if (!(_mm256_cvtsd_f64(weight_sum) > 0)) {  // an isolated vertex stays where it is
      result = _mm256_load_pd(positions + 4 * i);
    } else if constexpr (L1) {  // eq. (8): the fourth lane becomes 1 again
      result = _mm256_div_pd(sum, weight_sum);
    } else {  // eq. (6): a multiplication by 1/v_i instead of a long division; the fourth lane set to 1
      result = _mm256_blend_pd(_mm256_mul_pd(sum, _mm256_broadcast_sd(inverse_degree + i)), _mm256_set1_pd(1.0), 0x8);
    }
    _mm256_store_pd(out + 4 * i, result);
#else
    double sum[4] = {0, 0, 0, 0};
    for (int k = lower_offsets_[i]; k < lower_offsets_[i + 1]; ++k) {  // edges (j, i), j < i: x_j − v
      const Index e = lower_edges_[k];
      const double* pj = positions + 4 * Index(edge_a_[e]);
      const double* v = corrections + 4 * e;
      const double w = L1 ? weights[e] : 1.0;
      for (int c = 0; c < 4; ++c) sum[c] += w * pj[c] - v[c];
    }
    for (Index e = upper_offsets_[i]; e < upper_offsets_[i + 1]; ++e) {  // edges (i, j), j > i: x_j + v
      const double* pj = positions + 4 * Index(edge_b_[e]);
      const double* v = corrections + 4 * e;
      const double w = L1 ? weights[e] : 1.0;
      for (int c = 0; c < 4; ++c) sum[c] += w * pj[c] + v[c];
    }
    double* o = out + 4 * i;
    if (sum[3] > 0) {  // eq. (6) / eq. (8); the fourth lane becomes 1 again
      const double scale = L1 ? 1.0 / sum[3] : inverse_degree[i];
      for (int c = 0; c < 3; ++c) o[c] = sum[c] * scale;
      o[3] = 1;
    } else {  // an isolated vertex stays where it is
      const double* p = positions + 4 * i;
      for (int c = 0; c < 4; ++c) o[c] = p[c];
    }
#endif
  }
}

void MetricProjection::sweeps(Points& X, int count) const {
  CSHAPES_REQUIRE(X.rows() == n_, "metric projection: X has ", X.rows(), " rows, expected ", n_);
  if (count <= 0 || n_ == 0) return;
  const Index m = num_edges();
  positions_a_.resize(4 * n_);
  positions_b_.resize(4 * n_);
  corrections_.resize(4 * m);
  const bool l1 = options_.norm == ProjectionNorm::L1, dilation = options_.dilation > 1;
  if (l1) weights_.resize(m);
  const Index edge_blocks = (m + kEdgeBlock - 1) / kEdgeBlock;
  const Index vertex_blocks = (n_ + kVertexBlock - 1) / kVertexBlock;
  double* x = X.data();  // column-major n×3
  double* buffers[2] = {positions_a_.data(), positions_b_.data()};
#pragma omp parallel if (n_ >= kParallelMinVertices)
  {
#pragma omp for schedule(static)
    for (Index block = 0; block < vertex_blocks; ++block)
      for (Index i = block * kVertexBlock; i < std::min(n_, (block + 1) * kVertexBlock); ++i) {
        double* p = buffers[0] + 4 * i;
        p[0] = x[i];
        p[1] = x[n_ + i];
        p[2] = x[2 * n_ + i];
        p[3] = 1;
      }
    for (int step = 0; step < count; ++step) {
      const double* in = buffers[step % 2];
      double* out = buffers[(step + 1) % 2];
#pragma omp for schedule(static)
      for (Index block = 0; block < edge_blocks; ++block) {
        const Index first = block * kEdgeBlock, last = std::min(m, first + kEdgeBlock);
        if (l1) {
          if (dilation) edge_pass<true, true>(in, first, last);
          else edge_pass<true, false>(in, first, last);
        } else {
          if (dilation) edge_pass<false, true>(in, first, last);
          else edge_pass<false, false>(in, first, last);
        }
      }
#pragma omp for schedule(static)
      for (Index block = 0; block < vertex_blocks; ++block) {
        const Index first = block * kVertexBlock, last = std::min(n_, first + kVertexBlock);
        if (l1) vertex_pass<true>(in, out, first, last);
        else vertex_pass<false>(in, out, first, last);
      }
    }
    const double* result = buffers[count % 2];
#pragma omp for schedule(static)
    for (Index block = 0; block < vertex_blocks; ++block)
      for (Index i = block * kVertexBlock; i < std::min(n_, (block + 1) * kVertexBlock); ++i) {
        const double* p = result + 4 * i;
        x[i] = p[0];
        x[n_ + i] = p[1];
        x[2 * n_ + i] = p[2];
      }
  }
}

RelativeViolation MetricProjection::relative_violation(const Points& X) const {
  CSHAPES_REQUIRE(X.rows() == n_, "metric projection: X has ", X.rows(), " rows, expected ", n_);
  const Index m = num_edges();
  RelativeViolation v;
  if (m == 0) return v;
  const double* x = X.data();
  const double* y = x + n_;
  const double* z = y + n_;
  // Partial sums over fixed blocks of edges, added in block order: the same result on any number of threads.
  const Index blocks = (m + kViolationBlock - 1) / kViolationBlock;
  block_sums_.resize(blocks);
  block_maxima_.resize(blocks);
  double* sums = block_sums_.data();
  double* maxima = block_maxima_.data();
#pragma omp parallel for schedule(static) if (m >= 4 * kViolationBlock)
  for (Index block = 0; block < blocks; ++block) {
    alignas(32) double relative[kViolationBlock];
    const Index first = block * kViolationBlock;
    const int count = static_cast<int>(std::min(kViolationBlock, m - first));
    for (int k = 0; k < count; ++k) {
      const Index a = edge_a_[first + k], b = edge_b_[first + k];
      const double dx = x[a] - x[b], dy = y[a] - y[b], dz = z[a] - z[b];
      relative[k] = dx * dx + dy * dy + dz * dz;
    }
    const double* d = edge_rest_.data() + first;
    for (int k = 0; k < count; ++k) relative[k] = std::abs(std::sqrt(relative[k]) - d[k]) / d[k];
    // Four interleaved sums in a fixed pattern: not one long chain of dependent additions.
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
    sums[block] = (lanes[0] + lanes[1]) + (lanes[2] + lanes[3]);
    maxima[block] = std::max(std::max(lane_max[0], lane_max[1]), std::max(lane_max[2], lane_max[3]));
  }
  double total = 0;
  for (Index block = 0; block < blocks; ++block) {
    total += sums[block];
    v.max = std::max(v.max, maxima[block]);
  }
  v.mean = total / static_cast<double>(m);
  return v;
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
