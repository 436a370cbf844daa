// The triangular solves of operators/sparse_cholesky.cpp, compiled per instruction set: included there inside one
// namespace per set (under that set's `#pragma GCC target`, or none for the baseline). No headers here. The
// loops are k-wide AXPYs with no reduction and no contraction into fused multiply-adds (fp-contract=off
// where the set has them), so every set computes the same bytes, only more lanes at a time.

// y (n rows of k doubles) ← L⁻ᵀ L⁻¹ y for the factor L in compressed columns (colptr, row, value; the
// diagonal first in each column).
void solve_in_place(double* __restrict y, long n, long k, const int* colptr, const int* row, const double* value) {
  // L y = P b, column by column: each column of L updates the rows below its diagonal.
  for (long j = 0; j < n; ++j) {
    double* __restrict yj = y + j * k;
    const double inv = 1.0 / value[colptr[j]];
#pragma omp simd
    for (long c = 0; c < k; ++c) yj[c] *= inv;
    for (int q = colptr[j] + 1; q < colptr[j + 1]; ++q) {
      double* __restrict yi = y + static_cast<long>(row[q]) * k;
      const double v = value[q];
#pragma omp simd
      for (long c = 0; c < k; ++c) yi[c] -= v * yj[c];
    }
  }
  // Lᵀ x = y, backwards: row j of Lᵀ is column j of L.
  for (long j = n - 1; j >= 0; --j) {
    double* __restrict yj = y + j * k;
    for (int q = colptr[j] + 1; q < colptr[j + 1]; ++q) {
      const double* __restrict yi = y + static_cast<long>(row[q]) * k;
      const double v = value[q];
#pragma omp simd
      for (long c = 0; c < k; ++c) yj[c] -= v * yi[c];
    }
    const double inv = 1.0 / value[colptr[j]];
#pragma omp simd
    for (long c = 0; c < k; ++c) yj[c] *= inv;
  }
}
