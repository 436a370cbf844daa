// Internal to canon/coulomb_energy.cpp and canon/coulomb_fmm.cpp: the float particle-to-particle kernel.
//
// For up to 8 consecutive targets i0 … i0+count−1 and a list of source index ranges (all indices into the same
// float structure-of-arrays x, y, z) it adds, per target i,
//   potential[i] += Σ_j 1/r_ij,   force[i] += Σ_j (x_i − x_j)/r_ij³,   r_ij = max(‖x_i − x_j‖, floor)
// skipping j = i. Pair terms are float (AVX2: rsqrt + one Newton step, relative error ≈ 1e-7; elsewhere
// 1/sqrt), kept in registers, and flushed into the double accumulators at least every kFlushEvery sources, so
// float round-off never builds up over long sums. The loop is over sources with the 8 targets in the vector
// lanes: no horizontal reductions. Deterministic: the order of every addition is fixed by the inputs.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>

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
  double scale = 1;          // half the largest bounding-box extent (1 for a single point)
  float floor2 = 0;          // squared distance floor in normalized units, at least 1e-30
  double floor2_double = 0;  // the same in double
};
NormalizedPoints normalize_points(const Points& X, double min_distance);  // min_distance 0: the default

struct FloatPoints {
  const float* x;
  const float* y;
  const float* z;
};

#ifdef CSHAPES_COULOMB_AVX2

inline void p2p_block(const FloatPoints& p, Index i0, int count, const SourceRange* ranges, int num_ranges,
                      float floor2, double* potential, double* fx, double* fy, double* fz) {
  alignas(32) float tx[kBlock], ty[kBlock], tz[kBlock];
  for (int l = 0; l < kBlock; ++l) {  // pad a short block with its last target; padded lanes are dropped
    const Index i = i0 + (l < count ? l : count - 1);
    tx[l] = p.x[i], ty[l] = p.y[i], tz[l] = p.z[i];
  }
  const __m256 vx = _mm256_load_ps(tx), vy = _mm256_load_ps(ty), vz = _mm256_load_ps(tz);
  const __m256 vfloor2 = _mm256_set1_ps(floor2), half = _mm256_set1_ps(0.5f), three_halves = _mm256_set1_ps(1.5f);
  const __m256i lane_index =
      _mm256_add_epi32(_mm256_set1_epi32(static_cast<int32_t>(i0)), _mm256_setr_epi32(0, 1, 2, 3, 4, 5, 6, 7));
  __m256d dp[2] = {_mm256_setzero_pd(), _mm256_setzero_pd()}, dx[2] = {dp[0], dp[0]}, dy[2] = {dp[0], dp[0]},
          dz[2] = {dp[0], dp[0]};
  __m256 ap = _mm256_setzero_ps(), ax = ap, ay = ap, az = ap;
  int pending = 0;
  auto flush = [&]() {
    const __m256 a[4] = {ap, ax, ay, az};
    __m256d* d[4] = {dp, dx, dy, dz};
    for (int k = 0; k < 4; ++k) {
      d[k][0] = _mm256_add_pd(d[k][0], _mm256_cvtps_pd(_mm256_castps256_ps128(a[k])));
      d[k][1] = _mm256_add_pd(d[k][1], _mm256_cvtps_pd(_mm256_extractf128_ps(a[k], 1)));
    }
    ap = ax = ay = az = _mm256_setzero_ps();
    pending = 0;
  };
  for (int r = 0; r < num_ranges; ++r) {
    const int32_t begin = ranges[r].begin, end = ranges[r].end;
    const bool has_self = begin < i0 + count && i0 < end;
    for (int32_t j = begin; j < end; ++j) {
      const __m256 ddx = _mm256_sub_ps(vx, _mm256_broadcast_ss(p.x + j));
      const __m256 ddy = _mm256_sub_ps(vy, _mm256_broadcast_ss(p.y + j));
      const __m256 ddz = _mm256_sub_ps(vz, _mm256_broadcast_ss(p.z + j));
      __m256 r2 = _mm256_fmadd_ps(ddx, ddx, _mm256_fmadd_ps(ddy, ddy, _mm256_mul_ps(ddz, ddz)));
      r2 = _mm256_max_ps(r2, vfloor2);
      __m256 inv_r = _mm256_rsqrt_ps(r2);
      // One Newton step: y ← y (3/2 − r² y²/2), from 12 to ~23 correct bits.
      inv_r = _mm256_mul_ps(inv_r, _mm256_fnmadd_ps(_mm256_mul_ps(half, r2), _mm256_mul_ps(inv_r, inv_r), three_halves));
      if (has_self) {
        const __m256i same = _mm256_cmpeq_epi32(lane_index, _mm256_set1_epi32(j));
        inv_r = _mm256_andnot_ps(_mm256_castsi256_ps(same), inv_r);
      }
      const __m256 inv_r3 = _mm256_mul_ps(inv_r, _mm256_mul_ps(inv_r, inv_r));
      ap = _mm256_add_ps(ap, inv_r);
      ax = _mm256_fmadd_ps(ddx, inv_r3, ax);
      ay = _mm256_fmadd_ps(ddy, inv_r3, ay);
      az = _mm256_fmadd_ps(ddz, inv_r3, az);
      if (++pending == kFlushEvery) flush();
    }
  }
  flush();
  alignas(32) double out[4][kBlock];
  const __m256d* d[4] = {dp, dx, dy, dz};
  for (int k = 0; k < 4; ++k) {
    _mm256_store_pd(out[k], d[k][0]);
    _mm256_store_pd(out[k] + 4, d[k][1]);
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
    const float xi = p.x[i], yi = p.y[i], zi = p.z[i];
    double sp = 0, sx = 0, sy = 0, sz = 0;
    for (int r = 0; r < num_ranges; ++r) {
      for (int32_t chunk = ranges[r].begin; chunk < ranges[r].end; chunk += kFlushEvery) {
        const int32_t chunk_end = std::min<int32_t>(chunk + kFlushEvery, ranges[r].end);
        float ap = 0, ax = 0, ay = 0, az = 0;
#pragma omp simd reduction(+ : ap, ax, ay, az)
        for (int32_t j = chunk; j < chunk_end; ++j) {
          const float ddx = xi - p.x[j], ddy = yi - p.y[j], ddz = zi - p.z[j];
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
