// Internal to canon/coulomb_energy.cpp and canon/coulomb_fmm.cpp: the float particle-to-particle kernel.
//
// For up to kBlock consecutive targets i0 … i0+count−1 and a list of source index ranges (all indices into
// the same float structure-of-arrays x, y, z) it adds, per target i,
//   potential[i] += Σ_j 1/r_ij,   force[i] += Σ_j (x_i − x_j)/r_ij³,   r_ij = max(‖x_i − x_j‖, floor)
// skipping j = i. Pair terms are float (AVX2: rsqrt + one Newton step, relative error ≈ 1e-7; elsewhere
// 1/sqrt), kept in registers, and flushed into the double accumulators at least every kFlushEvery sources, so
// float round-off never builds up over long sums. The loop is over sources with the targets in the vector
// lanes: no horizontal reductions. Deterministic: the order of every addition is fixed by the inputs.
//
// Coordinates are split into float high and low parts (x = hi + lo, |lo| ≤ ulp(hi)/2) and differences are
// formed as (hi_i − hi_j) + (lo_i − lo_j): the first subtraction is exact for close points (Sterbenz), so the
// difference of two close points keeps ~1e-7 relative accuracy instead of 1e-7 of the box size. Without it a
// pair of random points 1e-3 apart in a unit box gets a 1e-4 relative force error, which dominates the
// gradient error of the points involved.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <type_traits>

#include "core/types.h"

#if defined(__AVX2__) && defined(__FMA__)
#include <immintrin.h>
#define CSHAPES_COULOMB_AVX2 1
#endif

namespace cshapes::coulomb_detail {

struct SourceRange {
  int32_t begin, end;  // [begin, end) indices into the coordinate arrays
};

constexpr int kBlock = 8;         // targets per call: one AVX register of floats
constexpr int kFlushEvery = 512;  // sources summed in float before flushing into double

// Coordinates mapped to the cube [-1, 1]³ (x' = (x − center)/scale), so float arithmetic never over- or
// underflows whatever the input's units; results are scaled back (potential /scale, gradient /scale²).
struct NormalizedPoints {
  Eigen::RowVector3d center = Eigen::RowVector3d::Zero();
  double scale = 1;  // half the largest bounding-box extent (1 for a single point)
  float floor2 = 0;  // squared distance floor in normalized units
};
NormalizedPoints normalize_points(const Points& X, double min_distance);  // min_distance 0: the default

struct FloatPoints {
  const float *x, *y, *z;           // high parts: float(x)
  const float *x_lo, *y_lo, *z_lo;  // low parts: float(x − float(x))
};

// Splits normalized double coordinates into the high and low float arrays of FloatPoints.
inline void split_float(double value, float& hi, float& lo) {
  hi = static_cast<float>(value);
  lo = static_cast<float>(value - static_cast<double>(hi));
}

#ifdef CSHAPES_COULOMB_AVX2

// kBlock / 8 AVX registers of targets per source load. Measured (direct float sum, n = 20,000, one thread):
// one register 2.5e9 pairs/s, two registers 2.1e9 (the extra live registers spill), so kBlock = 8.
inline void p2p_block(const FloatPoints& p, Index i0, int count, const SourceRange* ranges, int num_ranges,
                      float floor2, double* potential, double* fx, double* fy, double* fz) {
  constexpr int V = kBlock / 8;
  alignas(32) float t[6][kBlock];
  for (int l = 0; l < kBlock; ++l) {  // pad a short block with its last target; padded lanes are dropped
    const Index i = i0 + (l < count ? l : count - 1);
    t[0][l] = p.x[i], t[1][l] = p.y[i], t[2][l] = p.z[i];
    t[3][l] = p.x_lo[i], t[4][l] = p.y_lo[i], t[5][l] = p.z_lo[i];
  }
  __m256 vx[V], vy[V], vz[V], vx_lo[V], vy_lo[V], vz_lo[V];
  __m256i lane_index[V];
  for (int v = 0; v < V; ++v) {
    vx[v] = _mm256_load_ps(t[0] + 8 * v), vy[v] = _mm256_load_ps(t[1] + 8 * v);
    vz[v] = _mm256_load_ps(t[2] + 8 * v), vx_lo[v] = _mm256_load_ps(t[3] + 8 * v);
    vy_lo[v] = _mm256_load_ps(t[4] + 8 * v), vz_lo[v] = _mm256_load_ps(t[5] + 8 * v);
    lane_index[v] = _mm256_add_epi32(_mm256_set1_epi32(static_cast<int32_t>(i0 + 8 * v)),
                                     _mm256_setr_epi32(0, 1, 2, 3, 4, 5, 6, 7));
  }
  const __m256 vfloor2 = _mm256_set1_ps(floor2), half = _mm256_set1_ps(0.5f),
               three_halves = _mm256_set1_ps(1.5f);
  __m256d sum[V][4][2];  // double accumulators: [register][potential, x, y, z][low, high half]
  __m256 acc[V][4];      // float accumulators, flushed into sum
  for (int v = 0; v < V; ++v)
    for (int k = 0; k < 4; ++k) {
      sum[v][k][0] = sum[v][k][1] = _mm256_setzero_pd();
      acc[v][k] = _mm256_setzero_ps();
    }
  auto flush = [&]() {
    for (int v = 0; v < V; ++v)
      for (int k = 0; k < 4; ++k) {
        sum[v][k][0] = _mm256_add_pd(sum[v][k][0], _mm256_cvtps_pd(_mm256_castps256_ps128(acc[v][k])));
        sum[v][k][1] = _mm256_add_pd(sum[v][k][1], _mm256_cvtps_pd(_mm256_extractf128_ps(acc[v][k], 1)));
        acc[v][k] = _mm256_setzero_ps();
      }
  };
  // Sources [begin, end) with or without the i = j mask (a compile-time choice, so the common case pays
  // nothing for it).
  auto sum_sources = [&](int32_t begin, int32_t end, auto self_tag) {
    constexpr bool kSelf = decltype(self_tag)::value;
    for (int32_t j = begin; j < end; ++j) {
      const __m256 sx = _mm256_broadcast_ss(p.x + j), sy = _mm256_broadcast_ss(p.y + j),
                   sz = _mm256_broadcast_ss(p.z + j), sx_lo = _mm256_broadcast_ss(p.x_lo + j),
                   sy_lo = _mm256_broadcast_ss(p.y_lo + j), sz_lo = _mm256_broadcast_ss(p.z_lo + j);
      for (int v = 0; v < V; ++v) {
        const __m256 ddx = _mm256_add_ps(_mm256_sub_ps(vx[v], sx), _mm256_sub_ps(vx_lo[v], sx_lo));
        const __m256 ddy = _mm256_add_ps(_mm256_sub_ps(vy[v], sy), _mm256_sub_ps(vy_lo[v], sy_lo));
        const __m256 ddz = _mm256_add_ps(_mm256_sub_ps(vz[v], sz), _mm256_sub_ps(vz_lo[v], sz_lo));
        __m256 r2 = _mm256_fmadd_ps(ddx, ddx, _mm256_fmadd_ps(ddy, ddy, _mm256_mul_ps(ddz, ddz)));
        r2 = _mm256_max_ps(r2, vfloor2);
        __m256 inv_r = _mm256_rsqrt_ps(r2);
        // One Newton step: y ← y (3/2 − r² y²/2), from 12 to ~23 correct bits.
        inv_r = _mm256_mul_ps(
            inv_r, _mm256_fnmadd_ps(_mm256_mul_ps(half, r2), _mm256_mul_ps(inv_r, inv_r), three_halves));
        if constexpr (kSelf) {
          const __m256i same = _mm256_cmpeq_epi32(lane_index[v], _mm256_set1_epi32(j));
          inv_r = _mm256_andnot_ps(_mm256_castsi256_ps(same), inv_r);
        }
        const __m256 inv_r3 = _mm256_mul_ps(inv_r, _mm256_mul_ps(inv_r, inv_r));
        acc[v][0] = _mm256_add_ps(acc[v][0], inv_r);
        acc[v][1] = _mm256_fmadd_ps(ddx, inv_r3, acc[v][1]);
        acc[v][2] = _mm256_fmadd_ps(ddy, inv_r3, acc[v][2]);
        acc[v][3] = _mm256_fmadd_ps(ddz, inv_r3, acc[v][3]);
      }
    }
  };
  int pending = 0;
  for (int r = 0; r < num_ranges; ++r) {
    const bool has_self = ranges[r].begin < i0 + count && i0 < ranges[r].end;
    for (int32_t begin = ranges[r].begin; begin < ranges[r].end;) {
      const int32_t end = std::min<int32_t>(ranges[r].end, begin + (kFlushEvery - pending));
      if (has_self)
        sum_sources(begin, end, std::true_type{});
      else
        sum_sources(begin, end, std::false_type{});
      pending += end - begin;
      begin = end;
      if (pending == kFlushEvery) flush(), pending = 0;
    }
  }
  flush();
  alignas(32) double out[4][kBlock];
  for (int v = 0; v < V; ++v)
    for (int k = 0; k < 4; ++k) {
      _mm256_store_pd(out[k] + 8 * v, sum[v][k][0]);
      _mm256_store_pd(out[k] + 8 * v + 4, sum[v][k][1]);
    }
  for (int l = 0; l < count; ++l) {
    potential[i0 + l] += out[0][l];
    fx[i0 + l] += out[1][l];
    fy[i0 + l] += out[2][l];
    fz[i0 + l] += out[3][l];
  }
}

#else  // portable fallback with the same semantics

inline void p2p_block(const FloatPoints& p, Index i0, int count, const SourceRange* ranges, int num_ranges,
                      float floor2, double* potential, double* fx, double* fy, double* fz) {
  for (int l = 0; l < count; ++l) {
    const Index i = i0 + l;
    const float xi = p.x[i], yi = p.y[i], zi = p.z[i], xi_lo = p.x_lo[i], yi_lo = p.y_lo[i],
                zi_lo = p.z_lo[i];
    double sp = 0, sx = 0, sy = 0, sz = 0;
    for (int r = 0; r < num_ranges; ++r) {
      for (int32_t chunk = ranges[r].begin; chunk < ranges[r].end; chunk += kFlushEvery) {
        const int32_t chunk_end = std::min<int32_t>(chunk + kFlushEvery, ranges[r].end);
        float ap = 0, ax = 0, ay = 0, az = 0;
#pragma omp simd reduction(+ : ap, ax, ay, az)
        for (int32_t j = chunk; j < chunk_end; ++j) {
          const float ddx = (xi - p.x[j]) + (xi_lo - p.x_lo[j]), ddy = (yi - p.y[j]) + (yi_lo - p.y_lo[j]),
                      ddz = (zi - p.z[j]) + (zi_lo - p.z_lo[j]);
          const float r2 = std::max(ddx * ddx + ddy * ddy + ddz * ddz, floor2);
          const float inv_r = (j == i) ? 0.0f : 1.0f / std::sqrt(r2);
          const float inv_r3 = inv_r * inv_r * inv_r;
          ap += inv_r;
          ax += ddx * inv_r3;
          ay += ddy * inv_r3;
          az += ddz * inv_r3;
        }
        sp += ap, sx += ax, sy += ay, sz += az;
      }
    }
    potential[i] += sp;
    fx[i] += sx;
    fy[i] += sy;
    fz[i] += sz;
  }
}

#endif

// The FMM's near field, in local frames. Each source leaf keeps its points as floats relative to a frame
// origin near it (its parent cell's centre), and a block of kBlock targets is converted to that frame (in
// double, then rounded) once per source range, so a float difference carries ~1e-7 of the frame's size S
// instead of the bounding box's: the high/low split of FloatPoints is not needed, which saves 6 of the 24
// vector operations per pair. A pair closer than S/256 (where that rounding would exceed ~1e-5 of the
// distance: near-duplicate points) is left out of the float sum and summed exactly in double instead, so
// near-coincident points cost accuracy nowhere.
// Coordinates are stored scaled by 1/√2 (kFrameScale): with h = ‖d'‖² = r²/2 and y ≈ rsqrt(h), one Newton
// step is w = y (3 − h y²) = 2√2/r (to ~23 bits), so 1/r = w/(2√2) and d/r³ = d' w³/16: the constants are
// applied once per flush and the step costs 3 operations instead of 4.
// Same semantics as p2p_block otherwise: skips j = i, distance floor, float terms flushed into double at
// least every kFlushEvery sources, every addition in an order fixed by the inputs.
constexpr double kFrameScale = 0.70710678118654752440;
constexpr double kCloseFraction =
    1.0 / 256;  // pairs closer than this × the frame's size are summed in double

// Frame coordinate of a point: float((x − origin)·kFrameScale). The one rounding rule for targets and
// sources.
inline float frame_coordinate(double x, double origin) {
  return static_cast<float>((x - origin) * kFrameScale);
}

// Source points [begin, end) of the frame-coordinate arrays, in the frame with origin `origin` (normalized
// coordinates); close_h: pairs with h = ‖d'‖² below it are summed exactly (frame_close_h).
struct FramedRange {
  double origin[3];
  int32_t begin, end;
  float close_h;
};

// close_h of a frame of radius `frame_radius` (normalized units): h of a pair at kCloseFraction × radius,
// at least the smallest normal float so that a point and itself always count as close.
inline float frame_close_h(double frame_radius) {
  const double d = kCloseFraction * frame_radius * kFrameScale;
  return std::max(static_cast<float>(d * d), std::numeric_limits<float>::min());
}

// For the targets i0 … i0+count−1 (count ≤ kBlock; normalized double coordinates x, y, z, which are also the
// sources' exact coordinates) and the source ranges `ranges` (frame coordinates sx, sy, sz), adds the sums
// into potential[i], fx[i], fy[i], fz[i]. self_range: the index of the range that contains the targets
// themselves (source i0 + l is target lane l), or −1. floor2: squared distance floor (normalized units).
inline void p2p_framed_block(const double* x, const double* y, const double* z, Index i0, int count,
                             const FramedRange* ranges, int num_ranges, int self_range, const float* sx,
                             const float* sy, const float* sz, float floor2, double* potential, double* fx,
                             double* fy, double* fz) {
  constexpr double kPotentialScale = 0.35355339059327376220;  // 1/(2√2)
  constexpr double kForceScale = 1.0 / 16;
  const float half_floor2 = 0.5f * floor2;
  alignas(32) double target[3][kBlock];
  for (int l = 0; l < kBlock; ++l) {  // pad a short block with its last target; padded lanes are dropped
    const Index i = i0 + (l < count ? l : count - 1);
    target[0][l] = x[i], target[1][l] = y[i], target[2][l] = z[i];
  }
  double sum[4][kBlock] = {};    // potential and force sums before the frame's constants, per lane
  double exact[4][kBlock] = {};  // the close pairs' exact potential and force sums, per lane
  int pending = 0;
#ifdef CSHAPES_COULOMB_AVX2
  // The close pairs of targets t (frame coordinates) and sources [begin, end): the same float h as the
  // vector loop (the same IEEE operations), then the exact term in double.
  auto sum_close_pairs = [&](const float(&t)[3][kBlock], int32_t begin, int32_t end, float close_h) {
    for (int l = 0; l < count; ++l)
      for (int32_t j = begin; j < end; ++j) {
        const float dx = t[0][l] - sx[j], dy = t[1][l] - sy[j], dz = t[2][l] - sz[j];
        const float h = std::fma(dx, dx, std::fma(dy, dy, dz * dz));
        if (!(h < close_h) || j == i0 + l) continue;
        const double ex = target[0][l] - x[j], ey = target[1][l] - y[j], ez = target[2][l] - z[j];
        const double r2 = std::max(ex * ex + ey * ey + ez * ez, static_cast<double>(floor2));
        const double inv_r = 1 / std::sqrt(r2), inv_r3 = inv_r / r2;
        exact[0][l] += inv_r, exact[1][l] += ex * inv_r3, exact[2][l] += ey * inv_r3,
            exact[3][l] += ez * inv_r3;
      }
  };
  const __m256 floor = _mm256_set1_ps(half_floor2), three = _mm256_set1_ps(3.0f);
  const __m256i lanes = _mm256_add_epi32(_mm256_set1_epi32(static_cast<int32_t>(i0)),
                                         _mm256_setr_epi32(0, 1, 2, 3, 4, 5, 6, 7));
  __m256 ap = _mm256_setzero_ps(), ax = ap, ay = ap, az = ap;
  auto flush = [&]() {
    alignas(32) float a[4][kBlock];
    _mm256_store_ps(a[0], ap), _mm256_store_ps(a[1], ax), _mm256_store_ps(a[2], ay),
        _mm256_store_ps(a[3], az);
    ap = ax = ay = az = _mm256_setzero_ps();
    for (int k = 0; k < 4; ++k)
      for (int l = 0; l < kBlock; ++l) sum[k][l] += a[k][l];
  };
  // The same rounding as frame_coordinate: float((x − origin)·kFrameScale), four lanes at a time.
  auto to_frame = [&](const double* t, double origin) {
    const __m256d o = _mm256_set1_pd(origin), scale = _mm256_set1_pd(kFrameScale);
    const __m128 low = _mm256_cvtpd_ps(_mm256_mul_pd(_mm256_sub_pd(_mm256_load_pd(t), o), scale));
    const __m128 high = _mm256_cvtpd_ps(_mm256_mul_pd(_mm256_sub_pd(_mm256_load_pd(t + 4), o), scale));
    return _mm256_set_m128(high, low);
  };
  // The common case, optimistic: sums every pair and only tracks the smallest h (1 operation per pair instead
  // of 3); returns whether some pair was close, in which case the caller discards this pass.
  auto sum_sources_optimistic = [&](__m256 tx, __m256 ty, __m256 tz, int32_t begin, int32_t end,
                                    float close_h) {
    __m256 smallest = _mm256_set1_ps(std::numeric_limits<float>::max());
    for (int32_t j = begin; j < end; ++j) {
      const __m256 dx = _mm256_sub_ps(tx, _mm256_broadcast_ss(sx + j));
      const __m256 dy = _mm256_sub_ps(ty, _mm256_broadcast_ss(sy + j));
      const __m256 dz = _mm256_sub_ps(tz, _mm256_broadcast_ss(sz + j));
      const __m256 h0 = _mm256_fmadd_ps(dx, dx, _mm256_fmadd_ps(dy, dy, _mm256_mul_ps(dz, dz)));
      smallest = _mm256_min_ps(smallest, h0);
      const __m256 h = _mm256_max_ps(h0, floor);
      const __m256 r = _mm256_rsqrt_ps(h);
      const __m256 w = _mm256_mul_ps(r, _mm256_fnmadd_ps(h, _mm256_mul_ps(r, r), three));
      const __m256 w3 = _mm256_mul_ps(w, _mm256_mul_ps(w, w));
      ap = _mm256_add_ps(ap, w);
      ax = _mm256_fmadd_ps(dx, w3, ax);
      ay = _mm256_fmadd_ps(dy, w3, ay);
      az = _mm256_fmadd_ps(dz, w3, az);
    }
    return _mm256_movemask_ps(_mm256_cmp_ps(smallest, _mm256_set1_ps(close_h), _CMP_LT_OQ)) != 0;
  };
  // Leaves close pairs (and i = j) out; returns whether some pair other than i = j was close.
  auto sum_sources = [&](__m256 tx, __m256 ty, __m256 tz, int32_t begin, int32_t end, float close_h,
                         auto self_tag) {
    constexpr bool kSelf = decltype(self_tag)::value;
    const __m256 close_limit = _mm256_set1_ps(close_h);
    __m256 any_close = _mm256_setzero_ps();
    for (int32_t j = begin; j < end; ++j) {
      const __m256 dx = _mm256_sub_ps(tx, _mm256_broadcast_ss(sx + j));
      const __m256 dy = _mm256_sub_ps(ty, _mm256_broadcast_ss(sy + j));
      const __m256 dz = _mm256_sub_ps(tz, _mm256_broadcast_ss(sz + j));
      const __m256 h0 = _mm256_fmadd_ps(dx, dx, _mm256_fmadd_ps(dy, dy, _mm256_mul_ps(dz, dz)));
      __m256 close = _mm256_cmp_ps(h0, close_limit, _CMP_LT_OQ);
      const __m256 h = _mm256_max_ps(h0, floor);
      const __m256 r = _mm256_rsqrt_ps(h);
      __m256 w = _mm256_andnot_ps(close, _mm256_mul_ps(r, _mm256_fnmadd_ps(h, _mm256_mul_ps(r, r), three)));
      if constexpr (kSelf)  // i = j is close too, but needs no exact term
        close = _mm256_andnot_ps(_mm256_castsi256_ps(_mm256_cmpeq_epi32(lanes, _mm256_set1_epi32(j))), close);
      any_close = _mm256_or_ps(any_close, close);
      const __m256 w3 = _mm256_mul_ps(w, _mm256_mul_ps(w, w));
      ap = _mm256_add_ps(ap, w);
      ax = _mm256_fmadd_ps(dx, w3, ax);
      ay = _mm256_fmadd_ps(dy, w3, ay);
      az = _mm256_fmadd_ps(dz, w3, az);
    }
    return _mm256_movemask_ps(any_close) != 0;
  };
#else
  static_cast<void>(self_range);  // the scalar loop tells i = j by index
  float acc[4][kBlock] = {};
  auto flush = [&]() {
    for (int k = 0; k < 4; ++k)
      for (int l = 0; l < kBlock; ++l) sum[k][l] += acc[k][l], acc[k][l] = 0;
  };
#endif
  for (int r = 0; r < num_ranges; ++r) {
    const FramedRange& range = ranges[r];
    alignas(32) float t[3][kBlock];
#ifdef CSHAPES_COULOMB_AVX2
    const __m256 tx = to_frame(target[0], range.origin[0]), ty = to_frame(target[1], range.origin[1]),
                 tz = to_frame(target[2], range.origin[2]);
    bool any_close = false;
    const int32_t size = range.end - range.begin;
    if (r != self_range && size <= kFlushEvery) {  // one pass, optimistic first
      if (pending + size > kFlushEvery) flush(), pending = 0;
      const __m256 saved[4] = {ap, ax, ay, az};
      if (sum_sources_optimistic(tx, ty, tz, range.begin, range.end, range.close_h)) {
        ap = saved[0], ax = saved[1], ay = saved[2], az = saved[3];
        sum_sources(tx, ty, tz, range.begin, range.end, range.close_h, std::false_type{});
        _mm256_store_ps(t[0], tx), _mm256_store_ps(t[1], ty), _mm256_store_ps(t[2], tz);
        sum_close_pairs(t, range.begin, range.end, range.close_h);
      }
      pending += size;
      continue;
    }
#else
    for (int c = 0; c < 3; ++c)
      for (int l = 0; l < kBlock; ++l) t[c][l] = frame_coordinate(target[c][l], range.origin[c]);
#endif
    for (int32_t begin = range.begin; begin < range.end;) {
      const int32_t end = std::min<int32_t>(range.end, begin + (kFlushEvery - pending));
#ifdef CSHAPES_COULOMB_AVX2
      if (r == self_range)
        any_close |= sum_sources(tx, ty, tz, begin, end, range.close_h, std::true_type{});
      else
        any_close |= sum_sources(tx, ty, tz, begin, end, range.close_h, std::false_type{});
#else
      {
        // The lanes in SIMD registers (SSE2 in a portable build); each pair is classified once, its flag kept,
        // and a close pair's exact double term added from the flags (no second test that might round
        // differently).
        alignas(32) unsigned char close_flag[kFlushEvery][kBlock];
        const float close_h = range.close_h;
        int any_close = 0;
        for (int32_t j = begin; j < end; ++j) {
          const float xj = sx[j], yj = sy[j], zj = sz[j];
          unsigned char* flag = close_flag[j - begin];
          int row_close = 0;
#pragma omp simd reduction(| : row_close)
          for (int l = 0; l < kBlock; ++l) {
            const float dx = t[0][l] - xj, dy = t[1][l] - yj, dz = t[2][l] - zj;
            const float h0 = dx * dx + dy * dy + dz * dz;
            const int close = h0 < close_h;
            const float w = close ? 0.0f : 2.0f / std::sqrt(std::max(h0, half_floor2)), w3 = w * w * w;
            acc[0][l] += w, acc[1][l] += dx * w3, acc[2][l] += dy * w3, acc[3][l] += dz * w3;
            flag[l] = static_cast<unsigned char>(close);
            row_close |= close;
          }
          any_close |= row_close;
        }
        if (any_close)
          for (int32_t j = begin; j < end; ++j)
            for (int l = 0; l < count; ++l) {
              if (!close_flag[j - begin][l] || j == i0 + l) continue;  // i = j: no term
              const double ex = target[0][l] - x[j], ey = target[1][l] - y[j], ez = target[2][l] - z[j];
              const double r2 = std::max(ex * ex + ey * ey + ez * ez, static_cast<double>(floor2));
              const double inv_r = 1 / std::sqrt(r2), inv_r3 = inv_r / r2;
              exact[0][l] += inv_r, exact[1][l] += ex * inv_r3, exact[2][l] += ey * inv_r3,
                  exact[3][l] += ez * inv_r3;
            }
      }
#endif
      pending += end - begin;
      begin = end;
      if (pending == kFlushEvery) flush(), pending = 0;
    }
#ifdef CSHAPES_COULOMB_AVX2
    if (any_close) {
      _mm256_store_ps(t[0], tx), _mm256_store_ps(t[1], ty), _mm256_store_ps(t[2], tz);
      sum_close_pairs(t, range.begin, range.end, range.close_h);
    }
#endif
  }
  flush();
  for (int l = 0; l < count; ++l) {
    potential[i0 + l] += sum[0][l] * kPotentialScale + exact[0][l];
    fx[i0 + l] += sum[1][l] * kForceScale + exact[1][l];
    fy[i0 + l] += sum[2][l] * kForceScale + exact[2][l];
    fz[i0 + l] += sum[3][l] * kForceScale + exact[3][l];
  }
}

}  // namespace cshapes::coulomb_detail
