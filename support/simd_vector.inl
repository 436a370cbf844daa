// A thin float vector type V for the kernels compiled per instruction set (support/simd.h). Included inside a
// namespace of the includer, after `#pragma GCC target("avx2,fma")` with CSHAPES_SIMD_VECTOR_AVX2 defined,
// after `#pragma GCC target("avx2,fma,avx512f,avx512vl,avx512dq,avx512bw")` with CSHAPES_SIMD_VECTOR_AVX512,
// or with no target (the baseline) and CSHAPES_SIMD_VECTOR_SSE2; the includer includes <immintrin.h> and
// <cstdint> first. No headers here.
//
// For kLanes float lanes: F (a vector), M (a lane mask), I (int32 lanes); zero, set1, load/store (aligned to
// kAlign bytes), loadu/storeu (unaligned), broadcast, add, sub, mul, min, max, rsqrt, lt and gt (masks),
// zero_where(m, a), keep_where(m, a), mask_or, mask_and_not(a, b) = ~a & b, no_lanes, any, any_first(m, n)
// (any of the first n lanes), iota(base)
// (base, base + 1, …), lane_is(indices, j), to_frame(t, origin, s) (the lanes of double t[kLanes] as
// float((t − origin)·s)). AVX2 and AVX-512 also have fmadd(a, b, c) = a·b + c and fnmadd(a, b, c) = c − a·b
// (fused: one rounding); SSE2 has none, so a kernel that uses them has no baseline twin.
//
// rsqrt is the hardware's 12-bit estimate `rsqrtps` in every type (AVX-512 too: its own `vrsqrt14ps` is
// another table), so that one processor gives the same lanes under every target; the estimate itself differs
// between processor makers (it is specified only to its relative error).

#if defined(CSHAPES_SIMD_VECTOR_AVX2)

// Eight float lanes in a 256-bit register; masks are all-ones lanes.
struct V {
  using F = __m256;
  using M = __m256;
  using I = __m256i;
  static constexpr int kLanes = 8;
  static constexpr int kAlign = 32;
  static F zero() { return _mm256_setzero_ps(); }
  static F set1(float a) { return _mm256_set1_ps(a); }
  static F load(const float* p) { return _mm256_load_ps(p); }
  static void store(float* p, F a) { _mm256_store_ps(p, a); }
  static F loadu(const float* p) { return _mm256_loadu_ps(p); }
  static void storeu(float* p, F a) { _mm256_storeu_ps(p, a); }
  static F broadcast(const float* p) { return _mm256_broadcast_ss(p); }
  static F add(F a, F b) { return _mm256_add_ps(a, b); }
  static F sub(F a, F b) { return _mm256_sub_ps(a, b); }
  static F mul(F a, F b) { return _mm256_mul_ps(a, b); }
  static F min(F a, F b) { return _mm256_min_ps(a, b); }
  static F max(F a, F b) { return _mm256_max_ps(a, b); }
  static F fmadd(F a, F b, F c) { return _mm256_fmadd_ps(a, b, c); }
  static F fnmadd(F a, F b, F c) { return _mm256_fnmadd_ps(a, b, c); }
  static F rsqrt(F a) { return _mm256_rsqrt_ps(a); }
  static M lt(F a, F b) { return _mm256_cmp_ps(a, b, _CMP_LT_OQ); }
  static M gt(F a, F b) { return _mm256_cmp_ps(a, b, _CMP_GT_OQ); }
  static F zero_where(M m, F a) { return _mm256_andnot_ps(m, a); }
  static F keep_where(M m, F a) { return _mm256_and_ps(m, a); }
  static M mask_or(M a, M b) { return _mm256_or_ps(a, b); }
  static M mask_and_not(M a, M b) { return _mm256_andnot_ps(a, b); }
  static M no_lanes() { return _mm256_setzero_ps(); }
  static bool any(M m) { return _mm256_movemask_ps(m) != 0; }
  static bool any_first(M m, int n) { return (_mm256_movemask_ps(m) & ((1 << n) - 1)) != 0; }
  static I iota(int32_t base) {
    return _mm256_add_epi32(_mm256_set1_epi32(base), _mm256_setr_epi32(0, 1, 2, 3, 4, 5, 6, 7));
  }
  static M lane_is(I lanes, int32_t j) {
    return _mm256_castsi256_ps(_mm256_cmpeq_epi32(lanes, _mm256_set1_epi32(j)));
  }
  static F to_frame(const double* t, double origin, double frame_scale) {
    const __m256d o = _mm256_set1_pd(origin), scale = _mm256_set1_pd(frame_scale);
    const __m128 low = _mm256_cvtpd_ps(_mm256_mul_pd(_mm256_sub_pd(_mm256_load_pd(t), o), scale));
    const __m128 high = _mm256_cvtpd_ps(_mm256_mul_pd(_mm256_sub_pd(_mm256_load_pd(t + 4), o), scale));
    return _mm256_set_m128(high, low);
  }
};

#elif defined(CSHAPES_SIMD_VECTOR_AVX512)

// Sixteen float lanes in a 512-bit register; masks are mask registers.
struct V {
  using F = __m512;
  using M = __mmask16;
  using I = __m512i;
  static constexpr int kLanes = 16;
  static constexpr int kAlign = 64;
  static F zero() { return _mm512_setzero_ps(); }
  static F set1(float a) { return _mm512_set1_ps(a); }
  static F load(const float* p) { return _mm512_load_ps(p); }
  static void store(float* p, F a) { _mm512_store_ps(p, a); }
  static F loadu(const float* p) { return _mm512_loadu_ps(p); }
  static void storeu(float* p, F a) { _mm512_storeu_ps(p, a); }
  static F broadcast(const float* p) { return _mm512_set1_ps(*p); }
  static F add(F a, F b) { return _mm512_add_ps(a, b); }
  static F sub(F a, F b) { return _mm512_sub_ps(a, b); }
  static F mul(F a, F b) { return _mm512_mul_ps(a, b); }
  static F min(F a, F b) { return _mm512_min_ps(a, b); }
  static F max(F a, F b) { return _mm512_max_ps(a, b); }
  static F fmadd(F a, F b, F c) { return _mm512_fmadd_ps(a, b, c); }
  static F fnmadd(F a, F b, F c) { return _mm512_fnmadd_ps(a, b, c); }
  static F rsqrt(F a) {  // rsqrtps on each half, the other targets' estimate (see above)
    const __m256 low = _mm256_rsqrt_ps(_mm512_castps512_ps256(a));
    const __m256 high = _mm256_rsqrt_ps(_mm512_extractf32x8_ps(a, 1));
    return _mm512_insertf32x8(_mm512_castps256_ps512(low), high, 1);
  }
  static M lt(F a, F b) { return _mm512_cmp_ps_mask(a, b, _CMP_LT_OQ); }
  static M gt(F a, F b) { return _mm512_cmp_ps_mask(a, b, _CMP_GT_OQ); }
  static F zero_where(M m, F a) { return _mm512_maskz_mov_ps(static_cast<__mmask16>(~m), a); }
  static F keep_where(M m, F a) { return _mm512_maskz_mov_ps(m, a); }
  static M mask_or(M a, M b) { return static_cast<M>(a | b); }
  static M mask_and_not(M a, M b) { return static_cast<M>(~a & b); }
  static M no_lanes() { return 0; }
  static bool any(M m) { return m != 0; }
  static bool any_first(M m, int n) { return (m & ((1 << n) - 1)) != 0; }
  static I iota(int32_t base) {
    return _mm512_add_epi32(_mm512_set1_epi32(base),
                            _mm512_setr_epi32(0, 1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12, 13, 14, 15));
  }
  static M lane_is(I lanes, int32_t j) { return _mm512_cmpeq_epi32_mask(lanes, _mm512_set1_epi32(j)); }
  static F to_frame(const double* t, double origin, double frame_scale) {
    const __m512d o = _mm512_set1_pd(origin), scale = _mm512_set1_pd(frame_scale);
    const __m256 low = _mm512_cvtpd_ps(_mm512_mul_pd(_mm512_sub_pd(_mm512_load_pd(t), o), scale));
    const __m256 high = _mm512_cvtpd_ps(_mm512_mul_pd(_mm512_sub_pd(_mm512_load_pd(t + 8), o), scale));
    return _mm512_insertf32x8(_mm512_castps256_ps512(low), high, 1);
  }
};

#elif defined(CSHAPES_SIMD_VECTOR_SSE2)

// Four float lanes in a 128-bit register (SSE2, every x86-64); masks are all-ones lanes. No fused
// multiply-add.
struct V {
  using F = __m128;
  using M = __m128;
  using I = __m128i;
  static constexpr int kLanes = 4;
  static constexpr int kAlign = 16;
  static F zero() { return _mm_setzero_ps(); }
  static F set1(float a) { return _mm_set1_ps(a); }
  static F load(const float* p) { return _mm_load_ps(p); }
  static void store(float* p, F a) { _mm_store_ps(p, a); }
  static F loadu(const float* p) { return _mm_loadu_ps(p); }
  static void storeu(float* p, F a) { _mm_storeu_ps(p, a); }
  static F broadcast(const float* p) { return _mm_load1_ps(p); }
  static F add(F a, F b) { return _mm_add_ps(a, b); }
  static F sub(F a, F b) { return _mm_sub_ps(a, b); }
  static F mul(F a, F b) { return _mm_mul_ps(a, b); }
  static F min(F a, F b) { return _mm_min_ps(a, b); }
  static F max(F a, F b) { return _mm_max_ps(a, b); }
  static F rsqrt(F a) { return _mm_rsqrt_ps(a); }
  static M lt(F a, F b) { return _mm_cmplt_ps(a, b); }
  static M gt(F a, F b) { return _mm_cmpgt_ps(a, b); }
  static F zero_where(M m, F a) { return _mm_andnot_ps(m, a); }
  static F keep_where(M m, F a) { return _mm_and_ps(m, a); }
  static M mask_or(M a, M b) { return _mm_or_ps(a, b); }
  static M mask_and_not(M a, M b) { return _mm_andnot_ps(a, b); }
  static M no_lanes() { return _mm_setzero_ps(); }
  static bool any(M m) { return _mm_movemask_ps(m) != 0; }
  static bool any_first(M m, int n) { return (_mm_movemask_ps(m) & ((1 << n) - 1)) != 0; }
  static I iota(int32_t base) { return _mm_add_epi32(_mm_set1_epi32(base), _mm_setr_epi32(0, 1, 2, 3)); }
  static M lane_is(I lanes, int32_t j) { return _mm_castsi128_ps(_mm_cmpeq_epi32(lanes, _mm_set1_epi32(j))); }
  static F to_frame(const double* t, double origin, double frame_scale) {
    const __m128d o = _mm_set1_pd(origin), scale = _mm_set1_pd(frame_scale);
    const __m128 low = _mm_cvtpd_ps(_mm_mul_pd(_mm_sub_pd(_mm_load_pd(t), o), scale));
    const __m128 high = _mm_cvtpd_ps(_mm_mul_pd(_mm_sub_pd(_mm_load_pd(t + 2), o), scale));
    return _mm_movelh_ps(low, high);
  }
};

#endif
