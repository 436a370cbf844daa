// The M2L of canon/coulomb_fmm.cpp, compiled per instruction set: included there inside one namespace per set
// (under that set's `#pragma GCC target`, or none for the baseline), after StaticM2L and Cell. No headers
// here.

// accumulated[m] += Σ_k moments[k] · ∂^{m+k}(1/r)(R), lane by lane, with every table a compile-time constant
// (StaticM2L<P>::kTables), so that the fully unrolled loops address registers and fixed offsets.
template <int P>
inline void m2l_apply(const V4 R[3], const V4* __restrict moments, V4* __restrict accumulated) {
  using M2L = StaticM2L<P>;
  constexpr const typename M2L::Tables& t = M2L::kTables;
  V4 D[M2L::kCount];
  const V4 inv_r2 = 1.0 / (R[0] * R[0] + R[1] * R[1] + R[2] * R[2]);
  for (int l = 0; l < 4; ++l) D[0][l] = std::sqrt(inv_r2[l]);
#pragma GCC unroll 128
  for (int k = 1; k < M2L::kCount; ++k) {
    V4 s1 = R[t.axis1[k][0]] * D[t.index1[k][0]];
#pragma GCC unroll 3
    for (int q = 1; q < t.n1[k]; ++q) s1 += R[t.axis1[k][q]] * D[t.index1[k][q]];
    V4 s2 = {0, 0, 0, 0};
#pragma GCC unroll 3
    for (int q = 0; q < t.n2[k]; ++q) s2 += D[t.index2[k][q]];
    D[k] = -(t.c1[k] * s1 + t.c2[k] * s2) * inv_r2;
  }
#pragma GCC unroll 128
  for (int k = 1; k < M2L::kCount; ++k) D[k] *= t.factorial[k];
#pragma GCC unroll 1024
  for (int j = 0; j < M2L::kPairs; ++j) accumulated[t.pair_m[j]] += moments[t.pair_k[j]] * D[t.pair_mk[j]];
}

// L_m += Σ_b Σ_k (−1)^|k| M^b_k ∂^{m+k}(1/r)(z_a − z_b) over the sources b = list[0 … count) of the cell with
// expansion centre `center`: four sources per pass, one per lane, the lanes summed at the end in a fixed
// order. multipoles: the cells' moments, `stride` doubles per cell (the coefficient count rounded up to 4).
template <int P>
void m2l_cell(const double* center, const int32_t* list, size_t count, const Cell* cells,
              const double* multipoles, int stride, double* local) {
  constexpr int kCount = StaticM2L<P>::kCount;
  constexpr int kStride = (kCount + 3) / 4 * 4;  // = stride
  V4 moments[kStride], accumulated[kCount];
  double zero[kStride] = {};
  for (int m = 0; m < kCount; ++m) accumulated[m] = V4{0, 0, 0, 0};
  for (size_t g = 0; g < count; g += 4) {
    V4 R[3] = {};
    const double* M[4];
    for (int l = 0; l < 4; ++l) {
      if (g + l < count) {
        const Cell& B = cells[list[g + l]];
        for (int c = 0; c < 3; ++c) R[c][l] = center[c] - B.center[c];
        M[l] = multipoles + static_cast<size_t>(list[g + l]) * static_cast<size_t>(stride);
      } else {  // an empty lane: a harmless separation and no charge
        R[0][l] = 1, R[1][l] = 0, R[2][l] = 0;
        M[l] = zero;
      }
    }
    // moments[k][l] = M[l][k]: 4×4 transposes of the rows (read unaligned: baseline code allocated them).
    for (int k = 0; k < kStride; k += 4) {
      const V4 r0 = *reinterpret_cast<const UnalignedV4*>(M[0] + k),
               r1 = *reinterpret_cast<const UnalignedV4*>(M[1] + k),
               r2 = *reinterpret_cast<const UnalignedV4*>(M[2] + k),
               r3 = *reinterpret_cast<const UnalignedV4*>(M[3] + k);
      const V4 a01 = __builtin_shufflevector(r0, r1, 0, 4, 2, 6),
               b01 = __builtin_shufflevector(r0, r1, 1, 5, 3, 7),
               a23 = __builtin_shufflevector(r2, r3, 0, 4, 2, 6),
               b23 = __builtin_shufflevector(r2, r3, 1, 5, 3, 7);
      moments[k] = __builtin_shufflevector(a01, a23, 0, 1, 4, 5);
      moments[k + 1] = __builtin_shufflevector(b01, b23, 0, 1, 4, 5);
      moments[k + 2] = __builtin_shufflevector(a01, a23, 2, 3, 6, 7);
      moments[k + 3] = __builtin_shufflevector(b01, b23, 2, 3, 6, 7);
    }
    m2l_apply<P>(R, moments, accumulated);
  }
  for (int m = 0; m < kCount; ++m)
    local[m] += (accumulated[m][0] + accumulated[m][1]) + (accumulated[m][2] + accumulated[m][3]);
}

inline M2LCellFunction m2l_cell_function(int order) {
  switch (order) {
    case 1:
      return &m2l_cell<1>;
    case 2:
      return &m2l_cell<2>;
    case 3:
      return &m2l_cell<3>;
    case 4:
      return &m2l_cell<4>;
    case 5:
      return &m2l_cell<5>;
    case 6:
      return &m2l_cell<6>;
    default:
      return nullptr;
  }
}
