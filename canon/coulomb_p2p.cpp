// The particle-to-particle kernels of canon/coulomb_p2p.h for each instruction set of support/simd.h: written
// once (canon/coulomb_p2p_simd.inl) over a thin vector type per set, each compiled in its own namespace
// (under its own `#pragma GCC target` above the baseline, so no inline function of one set can stand in for
// another's at link time), and one dispatcher per kernel. Compiled with -ffp-contract=off (CMakeLists.txt):
// every target gives the same bytes.
#include "cshapes/canon/coulomb_p2p.h"

#include <immintrin.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <type_traits>

#include "cshapes/support/simd.h"

namespace cshapes::coulomb_detail {

// The baseline: the same kernels over SSE2's four lanes (every x86-64 has SSE2), so that it gives the AVX
// targets' bytes.
namespace baseline {
#define CSHAPES_SIMD_VECTOR_SSE2
#include "cshapes/support/simd_vector.inl"
#undef CSHAPES_SIMD_VECTOR_SSE2
#include "cshapes/canon/coulomb_p2p_simd.inl"
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
// gcc 12 warns falsely in its own AVX-512 intrinsics (_mm512_undefined_ps initialises a value from itself;
// _mm512_castps256_ps512 leaves the upper half undefined).
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wmaybe-uninitialized"
#pragma GCC diagnostic ignored "-Wuninitialized"
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
                      const float* sy, const float* sz, float floor2, bool refine, double* potential,
                      double* fx, double* fy, double* fz) {
  switch (simd_target()) {
    case SimdTarget::Avx512:
      return avx512::p2p_framed_block(x, y, z, i0, count, ranges, num_ranges, self_range, sx, sy, sz, floor2,
                                      refine, potential, fx, fy, fz);
    case SimdTarget::Avx2:
      return avx2::p2p_framed_block(x, y, z, i0, count, ranges, num_ranges, self_range, sx, sy, sz, floor2,
                                    refine, potential, fx, fy, fz);
    case SimdTarget::Baseline:
      break;
  }
  baseline::p2p_framed_block(x, y, z, i0, count, ranges, num_ranges, self_range, sx, sy, sz, floor2, refine,
                             potential, fx, fy, fz);
}

}  // namespace cshapes::coulomb_detail
