#include "cshapes/operators/sparse_cholesky.h"

#include <Eigen/SparseCholesky>
#include <chrono>
#include <future>
#include <memory>
#include <thread>

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

#ifdef CSHAPES_HAVE_CHOLMOD
namespace {

// One CHOLMOD factorisation that owns everything it touches (its copy of the lower triangle, its workspace,
// its factor and the arrays it fills), so that it can run to its end on a thread nobody waits for.
struct CholmodJob {
  SparseMatrix lower;
  int status = CHOLMOD_OK;
  bool ok = false;
  std::vector<int> colptr, row, perm;
  std::vector<double> value;

  void run() {
    cholmod_common common;
    cholmod_start(&common);
    common.print = 0;
    common.error_handler = nullptr;
    common.supernodal = CHOLMOD_SIMPLICIAL;
    common.final_ll = 1;
    cholmod_sparse view = sparse_view(lower);
    cholmod_factor* factor = cholmod_analyze(&view, &common);
    ok = factor && common.status == CHOLMOD_OK;
    ok = ok && cholmod_factorize(&view, factor, &common) && common.status == CHOLMOD_OK;
    // Packed, monotonic LL': column j is p[j] .. p[j+1]-1, its diagonal first.
    ok = ok && cholmod_change_factor(CHOLMOD_REAL, 1, 0, 1, 1, factor, &common);
    status = common.status;
    if (ok) {
      const Index n = lower.rows();
      const int* p = static_cast<const int*>(factor->p);
      const int* i = static_cast<const int*>(factor->i);
      const double* x = static_cast<const double*>(factor->x);
      const int* q = static_cast<const int*>(factor->Perm);
      colptr.assign(p, p + n + 1);
      row.assign(i, i + p[n]);
      value.assign(x, x + p[n]);
      perm.assign(q, q + n);
    }
    if (factor) cholmod_free_factor(&factor, &common);
    cholmod_finish(&common);
  }
};

}  // namespace
#endif

void SparseCholesky::factorize(const SparseMatrix& A, const std::string& context, const std::string& what,
                               const ProgressFn& poll) {
  report_progress_in_parallel(poll, "", 0, 0);
#ifdef CSHAPES_HAVE_CHOLMOD
  auto job = std::make_shared<CholmodJob>();
  job->lower = A.triangularView<Eigen::Lower>();
  job->lower.makeCompressed();
  if (!poll) {
    job->run();
  } else {
    // Neither the ordering nor the numeric factorisation can be interrupted inside, and at a million vertices
    // each takes seconds: the job runs on its own thread while this one keeps polling. A stop is answered at
    // once; the job is left to finish on its own, holding only what it owns, and is then discarded.
    auto done = std::make_shared<std::promise<void>>();
    std::future<void> finished = done->get_future();
    std::thread([job, done] {
      job->run();
      done->set_value();
    }).detach();
    while (finished.wait_for(std::chrono::milliseconds(20)) != std::future_status::ready)
      report_progress_in_parallel(poll, "", 0, 0);
  }
  if (job->ok) {
    n_ = A.rows();
    colptr_ = std::move(job->colptr);
    row_ = std::move(job->row);
    value_ = std::move(job->value);
    perm_ = std::move(job->perm);
  }
  CSHAPES_REQUIRE(job->ok, context, ": CHOLMOD could not factorise the ", what, " matrix (status ", job->status,
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
