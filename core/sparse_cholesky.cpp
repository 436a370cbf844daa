#include "core/sparse_cholesky.h"

#include <Eigen/SparseCholesky>

#include "core/error.h"

#ifdef CSHAPES_HAVE_CHOLMOD
#include <cholmod.h>
#endif

namespace cshapes {

namespace {

using SparseMatrix = Eigen::SparseMatrix<double>;

#ifdef CSHAPES_HAVE_CHOLMOD
cholmod_sparse sparse_view(SparseMatrix& lower) {
  cholmod_sparse s;
  s.nrow = lower.rows();
  s.ncol = lower.cols();
  s.nzmax = lower.nonZeros();
  s.p = lower.outerIndexPtr();
  s.i = lower.innerIndexPtr();
  s.nz = nullptr;
  s.x = lower.valuePtr();
  s.z = nullptr;
  s.stype = -1;  // symmetric, lower triangle stored
  s.itype = CHOLMOD_INT;
  s.xtype = CHOLMOD_REAL;
  s.dtype = CHOLMOD_DOUBLE;
  s.sorted = 1;
  s.packed = 1;
  return s;
}
#endif

}  // namespace

void SparseCholesky::factorize(const SparseMatrix& A, const std::string& context, const std::string& what) {
  n_ = A.rows();
#ifdef CSHAPES_HAVE_CHOLMOD
  cholmod_common common;
  cholmod_start(&common);
  common.print = 0;
  common.error_handler = nullptr;
  common.supernodal = CHOLMOD_SIMPLICIAL;
  common.final_ll = 1;
  SparseMatrix lower = A.triangularView<Eigen::Lower>();
  lower.makeCompressed();
  cholmod_sparse view = sparse_view(lower);
  cholmod_factor* factor = cholmod_analyze(&view, &common);
  bool ok = factor && common.status == CHOLMOD_OK;
  ok = ok && cholmod_factorize(&view, factor, &common) && common.status == CHOLMOD_OK;
  // Packed, monotonic LL': column j is p[j] .. p[j+1]-1, its diagonal first.
  ok = ok && cholmod_change_factor(CHOLMOD_REAL, 1, 0, 1, 1, factor, &common);
  const int status = common.status;
  if (ok) {
    const int* p = static_cast<const int*>(factor->p);
    const int* i = static_cast<const int*>(factor->i);
    const double* x = static_cast<const double*>(factor->x);
    const int* perm = static_cast<const int*>(factor->Perm);
    colptr_.assign(p, p + n_ + 1);
    row_.assign(i, i + p[n_]);
    value_.assign(x, x + p[n_]);
    perm_.assign(perm, perm + n_);
  }
  if (factor) cholmod_free_factor(&factor, &common);
  cholmod_finish(&common);
  CSHAPES_REQUIRE(ok, context, ": CHOLMOD could not factorise the ", what, " matrix (status ", status,
                  "; not positive definite: degenerate or inverted triangles?)");
#else
  Eigen::SimplicialLLT<SparseMatrix> llt(A);
  CSHAPES_REQUIRE(llt.info() == Eigen::Success, context, ": the ", what,
                  " matrix could not be factorised; degenerate triangles?");
  // Eigen: P A Pᵀ = L Lᵀ with (P x)[P.indices()[i]] = x[i]; row k of the permuted system is row perm[k] of A.
  SparseMatrix L = llt.matrixL();
  L.makeCompressed();
  colptr_.assign(L.outerIndexPtr(), L.outerIndexPtr() + n_ + 1);
  row_.assign(L.innerIndexPtr(), L.innerIndexPtr() + L.nonZeros());
  value_.assign(L.valuePtr(), L.valuePtr() + L.nonZeros());
  perm_.resize(n_);
  for (Index i = 0; i < n_; ++i) perm_[llt.permutationP().indices()[i]] = static_cast<int>(i);
#endif
}

void SparseCholesky::solve(Block& B, Block& work) const {
  const Index k = B.cols();
  work.resize(n_, k);
  double* __restrict y = work.data();
  for (Index r = 0; r < n_; ++r) work.row(r) = B.row(perm_[r]);
  // L y = P b, column by column: each column of L updates the rows below its diagonal.
  for (Index j = 0; j < n_; ++j) {
    double* __restrict yj = y + j * k;
    const double inv = 1.0 / value_[colptr_[j]];
#pragma omp simd
    for (Index c = 0; c < k; ++c) yj[c] *= inv;
    for (int q = colptr_[j] + 1; q < colptr_[j + 1]; ++q) {
      double* __restrict yi = y + static_cast<Index>(row_[q]) * k;
      const double v = value_[q];
#pragma omp simd
      for (Index c = 0; c < k; ++c) yi[c] -= v * yj[c];
    }
  }
  // Lᵀ x = y, backwards: row j of Lᵀ is column j of L.
  for (Index j = n_ - 1; j >= 0; --j) {
    double* __restrict yj = y + j * k;
    for (int q = colptr_[j] + 1; q < colptr_[j + 1]; ++q) {
      const double* __restrict yi = y + static_cast<Index>(row_[q]) * k;
      const double v = value_[q];
#pragma omp simd
      for (Index c = 0; c < k; ++c) yj[c] -= v * yi[c];
    }
    const double inv = 1.0 / value_[colptr_[j]];
#pragma omp simd
    for (Index c = 0; c < k; ++c) yj[c] *= inv;
  }
  for (Index r = 0; r < n_; ++r) B.row(perm_[r]) = work.row(r);
}

std::string SparseCholesky::backend() {
#ifdef CSHAPES_HAVE_CHOLMOD
  return "cholmod";
#else
  return "eigen-llt";
#endif
}

}  // namespace cshapes
