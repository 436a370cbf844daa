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

}  // namespace cshapes::coulomb_detail
