// The particle-to-particle kernels of canon/coulomb_p2p.h for each instruction set of support/simd.h: the
// baseline (SSE2, written portably) here, the vector ones from canon/coulomb_p2p_simd.inl over a thin
// vector type per set, each compiled under its own `#pragma GCC target` in its own namespace (so no inline
// function of one set can stand in for another's at link time), and one dispatcher per kernel.
#include "cshapes/canon/coulomb_p2p.h"

#include <immintrin.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <type_traits>

#include "cshapes/support/simd.h"

namespace cshapes::coulomb_detail {

namespace baseline {

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

// The lanes of one block: as many as an AVX register holds, so that the compiler's SSE2 code keeps two
// registers per quantity.
constexpr int kLanes = 8;

// One block (count ≤ kLanes) of p2p_framed_block.
void p2p_framed_lanes(const double* x, const double* y, const double* z, Index i0, int count,
                      const FramedRange* ranges, int num_ranges, const float* sx, const float* sy,
                      const float* sz, float floor2, double* potential, double* fx, double* fy, double* fz) {
  constexpr double kPotentialScale = 0.35355339059327376220;  // 1/(2√2)
  constexpr double kForceScale = 1.0 / 16;
  const float half_floor2 = 0.5f * floor2;
  double target[3][kLanes];
  for (int l = 0; l < kLanes; ++l) {  // pad a short block with its last target; padded lanes are dropped
    const Index i = i0 + (l < count ? l : count - 1);
    target[0][l] = x[i], target[1][l] = y[i], target[2][l] = z[i];
  }
  double sum[4][kLanes] = {};    // potential and force sums before the frame's constants, per lane
  double exact[4][kLanes] = {};  // the close pairs' exact potential and force sums, per lane
  float acc[4][kLanes] = {};
  auto flush = [&]() {
    for (int k = 0; k < 4; ++k)
      for (int l = 0; l < kLanes; ++l) sum[k][l] += acc[k][l], acc[k][l] = 0;
  };
  int pending = 0;
  for (int r = 0; r < num_ranges; ++r) {
    const FramedRange& range = ranges[r];
    alignas(32) float t[3][kLanes];
    for (int c = 0; c < 3; ++c)
      for (int l = 0; l < kLanes; ++l) t[c][l] = frame_coordinate(target[c][l], range.origin[c]);
    for (int32_t begin = range.begin; begin < range.end;) {
      const int32_t end = std::min<int32_t>(range.end, begin + (kFlushEvery - pending));
      // The lanes in SIMD registers; each pair is classified once, its flag kept, and a close pair's exact
      // double term added from the flags (no second test that might round differently).
      alignas(32) unsigned char close_flag[kFlushEvery][kLanes];
      const float close_h = range.close_h;
      int any_close = 0;
      for (int32_t j = begin; j < end; ++j) {
        const float xj = sx[j], yj = sy[j], zj = sz[j];
        unsigned char* flag = close_flag[j - begin];
        int row_close = 0;
#pragma omp simd reduction(| : row_close)
        for (int l = 0; l < kLanes; ++l) {
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
      pending += end - begin;
      begin = end;
      if (pending == kFlushEvery) flush(), pending = 0;
    }
  }
  flush();
  for (int l = 0; l < count; ++l) {
    potential[i0 + l] += sum[0][l] * kPotentialScale + exact[0][l];
    fx[i0 + l] += sum[1][l] * kForceScale + exact[1][l];
    fy[i0 + l] += sum[2][l] * kForceScale + exact[2][l];
    fz[i0 + l] += sum[3][l] * kForceScale + exact[3][l];
  }
}

void p2p_framed_block(const double* x, const double* y, const double* z, Index i0, int count,
                      const FramedRange* ranges, int num_ranges, const float* sx, const float* sy,
                      const float* sz, float floor2, double* potential, double* fx, double* fy, double* fz) {
  for (int first = 0; first < count; first += kLanes)
    p2p_framed_lanes(x, y, z, i0 + first, std::min(kLanes, count - first), ranges, num_ranges, sx, sy, sz,
                     floor2, potential, fx, fy, fz);
}

}  // namespace baseline

#pragma GCC push_options
#pragma GCC target("avx2,fma")
namespace avx2 {
#define CSHAPES_SIMD_VECTOR_AVX2
#include "cshapes/support/simd_vector.inl"
#undef CSHAPES_SIMD_VECTOR_AVX2
#include "cshapes/canon/coulomb_p2p_simd.inl"
}  // namespace avx2
#pragma GCC pop_options

#pragma GCC push_options
#pragma GCC target("avx2,fma,avx512f,avx512vl,avx512dq,avx512bw")
// gcc 12 warns falsely in its own AVX-512 intrinsics (_mm512_undefined_ps initialises a value from itself).
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wmaybe-uninitialized"
namespace avx512 {
#define CSHAPES_SIMD_VECTOR_AVX512
#include "cshapes/support/simd_vector.inl"
#undef CSHAPES_SIMD_VECTOR_AVX512
#include "cshapes/canon/coulomb_p2p_simd.inl"
}  // namespace avx512
#pragma GCC diagnostic pop
#pragma GCC pop_options

void p2p_block(const FloatPoints& p, Index i0, int count, const SourceRange* ranges, int num_ranges,
               float floor2, double* potential, double* fx, double* fy, double* fz) {
  switch (simd_target()) {
    case SimdTarget::Avx512:
      return avx512::p2p_block(p, i0, count, ranges, num_ranges, floor2, potential, fx, fy, fz);
    case SimdTarget::Avx2:
      return avx2::p2p_block(p, i0, count, ranges, num_ranges, floor2, potential, fx, fy, fz);
    case SimdTarget::Baseline:
      break;
  }
  baseline::p2p_block(p, i0, count, ranges, num_ranges, floor2, potential, fx, fy, fz);
}

void p2p_framed_block(const double* x, const double* y, const double* z, Index i0, int count,
                      const FramedRange* ranges, int num_ranges, int self_range, const float* sx,
                      const float* sy, const float* sz, float floor2, double* potential, double* fx,
                      double* fy, double* fz) {
  switch (simd_target()) {
    case SimdTarget::Avx512:
      return avx512::p2p_framed_block(x, y, z, i0, count, ranges, num_ranges, self_range, sx, sy, sz, floor2,
                                      potential, fx, fy, fz);
    case SimdTarget::Avx2:
      return avx2::p2p_framed_block(x, y, z, i0, count, ranges, num_ranges, self_range, sx, sy, sz, floor2,
                                    potential, fx, fy, fz);
    case SimdTarget::Baseline:
      break;
  }
  baseline::p2p_framed_block(x, y, z, i0, count, ranges, num_ranges, sx, sy, sz, floor2, potential, fx, fy,
                             fz);
}

}  // namespace cshapes::coulomb_detail
