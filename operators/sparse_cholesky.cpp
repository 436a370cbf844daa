#include "cshapes/operators/sparse_cholesky.h"

#include <Eigen/SparseCholesky>

#include "cshapes/support/error.h"
#include "cshapes/support/progress.h"
#include "cshapes/support/simd.h"

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

namespace baseline {
#include "cshapes/operators/sparse_cholesky_simd.inl"
}  // namespace baseline
#pragma GCC push_options
#pragma GCC target("avx2,fma")
#pragma GCC optimize("fp-contract=off")
namespace avx2 {
#include "cshapes/operators/sparse_cholesky_simd.inl"
}  // namespace avx2
#pragma GCC pop_options
#pragma GCC push_options
#pragma GCC target("avx2,fma,avx512f,avx512vl,avx512dq,avx512bw")
#pragma GCC optimize("fp-contract=off")
namespace avx512 {
#include "cshapes/operators/sparse_cholesky_simd.inl"
}  // namespace avx512
#pragma GCC pop_options

}  // namespace

void SparseCholesky::factorize(const SparseMatrix& A, const std::string& context, const std::string& what,
                               const ProgressFn& poll) {
  report_progress_in_parallel(poll, "", 0, 0);
#ifdef CSHAPES_HAVE_CHOLMOD
  // CHOLMOD's workspace and factor, freed however this function is left (a poll may throw between steps).
  struct Cholmod {
    cholmod_common common;
    cholmod_factor* factor = nullptr;
    Cholmod() { cholmod_start(&common); }
    ~Cholmod() {
      if (factor) cholmod_free_factor(&factor, &common);
      cholmod_finish(&common);
    }
  } cholmod;
  cholmod_common& common = cholmod.common;
  common.print = 0;
  common.error_handler = nullptr;
  common.supernodal = CHOLMOD_SIMPLICIAL;
  common.final_ll = 1;
  SparseMatrix lower = A.triangularView<Eigen::Lower>();
  lower.makeCompressed();
  cholmod_sparse view = sparse_view(lower);
  cholmod_factor*& factor = cholmod.factor;
  factor = cholmod_analyze(&view, &common);
  bool ok = factor && common.status == CHOLMOD_OK;
  report_progress_in_parallel(poll, "", 0, 0);
  ok = ok && cholmod_factorize(&view, factor, &common) && common.status == CHOLMOD_OK;
  report_progress_in_parallel(poll, "", 0, 0);
  // Packed, monotonic LL': column j is p[j] .. p[j+1]-1, its diagonal first.
  ok = ok && cholmod_change_factor(CHOLMOD_REAL, 1, 0, 1, 1, factor, &common);
  const int status = common.status;
  if (ok) {
    n_ = A.rows();
    const int* p = static_cast<const int*>(factor->p);
    const int* i = static_cast<const int*>(factor->i);
    const double* x = static_cast<const double*>(factor->x);
    const int* perm = static_cast<const int*>(factor->Perm);
    colptr_.assign(p, p + n_ + 1);
    row_.assign(i, i + p[n_]);
    value_.assign(x, x + p[n_]);
    perm_.assign(perm, perm + n_);
  }
  CSHAPES_REQUIRE(ok, context, ": CHOLMOD could not factorise the ", what, " matrix (status ", status,
                  "; not positive definite: degenerate or inverted triangles?)");
#else
  Eigen::SimplicialLLT<SparseMatrix> llt(A);
  report_progress_in_parallel(poll, "", 0, 0);
  CSHAPES_REQUIRE(llt.info() == Eigen::Success, context, ": the ", what,
                  " matrix could not be factorised; degenerate triangles?");
  n_ = A.rows();
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
  switch (simd_target()) {
    case SimdTarget::Avx512:
      avx512::solve_in_place(y, n_, k, colptr_.data(), row_.data(), value_.data());
      break;
    case SimdTarget::Avx2:
      avx2::solve_in_place(y, n_, k, colptr_.data(), row_.data(), value_.data());
      break;
    case SimdTarget::Baseline:
      baseline::solve_in_place(y, n_, k, colptr_.data(), row_.data(), value_.data());
      break;
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
