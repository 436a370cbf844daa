// The vector parts of the metric projection's sweep (canon/metric_projection.cpp): four edges or one vertex
// record (x, y, z, weight) per 256-bit register of doubles. Included inside one namespace per instruction
// set, under that set's `#pragma GCC target` (no headers here: the includer provides them); the AVX-512
// target compiles the same 256-bit code with its 32 registers.

// Edges [e, e + 4k) ⊆ [e, last) of edge_pass, whole groups of four; returns the first edge left.
template <bool L1, bool Dilation>
inline Index edge_pass_vector(const double* positions, const int* a, const int* b, const int* slot_a,
                              const int* slot_b, const double* rest, double* slots, Index e, Index last,
                              const EdgeParameters& p) {
  // Four edges at a time: the square roots and divisions, the bulk of the arithmetic, run four-wide.
  const __m256d one = _mm256_set1_pd(1.0), tiny = _mm256_set1_pd(1e-12);
  for (; e + 4 <= last; e += 4) {
    __m256d pa[4], pb[4], u[4];
    for (int k = 0; k < 4; ++k) {
      pa[k] = _mm256_load_pd(positions + 4 * Index(a[e + k]));
      pb[k] = _mm256_load_pd(positions + 4 * Index(b[e + k]));
      u[k] = _mm256_sub_pd(pa[k], pb[k]);  // fourth lane: 1 − 1 = 0
    }
    // The four squared lengths in one vector.
    const __m256d h01 = _mm256_hadd_pd(_mm256_mul_pd(u[0], u[0]), _mm256_mul_pd(u[1], u[1]));
    const __m256d h23 = _mm256_hadd_pd(_mm256_mul_pd(u[2], u[2]), _mm256_mul_pd(u[3], u[3]));
    const __m256d r = _mm256_sqrt_pd(
        _mm256_add_pd(_mm256_permute2f128_pd(h01, h23, 0x20), _mm256_permute2f128_pd(h01, h23, 0x31)));
    const __m256d d = _mm256_loadu_pd(rest + e);
    __m256d target = d, w = one;
    if constexpr (Dilation)
      target = _mm256_min_pd(_mm256_max_pd(r, _mm256_mul_pd(d, _mm256_set1_pd(p.inv_dilation))),
                             _mm256_mul_pd(d, _mm256_set1_pd(p.dilation)));
    if constexpr (L1) {
      const __m256d deviation = _mm256_andnot_pd(_mm256_set1_pd(-0.0), _mm256_sub_pd(r, d));
      w = _mm256_div_pd(one, _mm256_max_pd(deviation, _mm256_mul_pd(d, _mm256_set1_pd(p.floor))));
    }
    const __m256d apart = _mm256_cmp_pd(r, _mm256_mul_pd(tiny, d), _CMP_GT_OQ);
    // t / r where the endpoints are apart, 0 where they coincide (divided by 1 there: no infinities).
    const __m256d scale = _mm256_and_pd(apart, _mm256_div_pd(target, _mm256_blendv_pd(one, r, apart)));
    const __m256d lane_scale[4] = {_mm256_permute4x64_pd(scale, 0x00), _mm256_permute4x64_pd(scale, 0x55),
                                   _mm256_permute4x64_pd(scale, 0xAA), _mm256_permute4x64_pd(scale, 0xFF)};
    const __m256d lane_w[4] = {_mm256_permute4x64_pd(w, 0x00), _mm256_permute4x64_pd(w, 0x55),
                               _mm256_permute4x64_pd(w, 0xAA), _mm256_permute4x64_pd(w, 0xFF)};
    for (int k = 0; k < 4; ++k) {
      const __m256d v = _mm256_mul_pd(lane_scale[k], u[k]);
      __m256d to_a = _mm256_add_pd(pb[k], v), to_b = _mm256_sub_pd(pa[k], v);
      if constexpr (L1) {
        to_a = _mm256_mul_pd(lane_w[k], to_a);
        to_b = _mm256_mul_pd(lane_w[k], to_b);
      }
      _mm256_store_pd(slots + 4 * Index(slot_a[e + k]), to_a);
      _mm256_store_pd(slots + 4 * Index(slot_b[e + k]), to_b);
    }
    const int apart_mask = _mm256_movemask_pd(apart);
    if (apart_mask != 0xF)  // rare: coincident endpoints, redone one by one
      for (int k = 0; k < 4; ++k)
        if (!(apart_mask & (1 << k)))
          project_edge<L1, Dilation>(positions + 4 * Index(a[e + k]), positions + 4 * Index(b[e + k]),
                                     rest[e + k], p, slots + 4 * Index(slot_a[e + k]),
                                     slots + 4 * Index(slot_b[e + k]));
  }
  return e;
}

// Vertices [first, last) of vertex_pass.
template <bool L1>
inline void vertex_pass_vector(const double* positions, double* out, const double* slots,
                               const double* inverse_degree, const int* offsets, Index first, Index last) {
  for (Index i = first; i < last; ++i) {
    const int begin = offsets[i], end = offsets[i + 1];
    __m256d sum = _mm256_setzero_pd();
    for (int k = begin; k < end; ++k) sum = _mm256_add_pd(sum, _mm256_load_pd(slots + 4 * Index(k)));
    __m256d result;
    if (begin == end) {  // an isolated vertex stays where it is
      result = _mm256_load_pd(positions + 4 * i);
    } else if constexpr (L1) {  // eq. (8); the fourth lane becomes 1 again
      result = _mm256_div_pd(sum, _mm256_permute4x64_pd(sum, 0xFF));
    } else {  // eq. (6): a multiplication by 1/v_i instead of a long division; the fourth lane set to 1
      result = _mm256_blend_pd(_mm256_mul_pd(sum, _mm256_broadcast_sd(inverse_degree + i)),
                               _mm256_set1_pd(1.0), 0x8);
    }
    _mm256_store_pd(out + 4 * i, result);
  }
}
