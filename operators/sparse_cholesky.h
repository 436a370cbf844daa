// A sparse symmetric positive definite matrix factorised once (P A Pᵀ = L Lᵀ) and solved for blocks of
// right-hand sides: the factorisation behind the heat method (geodesics/heat_method.h) and the shift-invert
// eigensolver of the Laplace–Beltrami operator (operators/laplace_beltrami.h).
//
// The factorisation is SuiteSparse CHOLMOD's when cshapes was built with it (simplicial: with the reference
// BLAS of a stock system its supernodal solve is slower per block), Eigen's SimplicialLLT otherwise. The
// triangular solves are ours: one pass over L per block of k right-hand sides stored row by row, each nonzero
// of L one k-wide vectorised AXPY (CHOLMOD's own solve handles at most 4 columns per pass). solve() may run
// concurrently from several threads.
#pragma once

#include <Eigen/SparseCore>
#include <string>
#include <vector>

#include "cshapes/support/progress.h"
#include "cshapes/support/types.h"

namespace cshapes {

class SparseCholesky {
 public:
  // Right-hand sides, one row per unknown: the k values of a row are contiguous.
  using Block = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;

  // A: symmetric with both triangles stored. Throws cshapes::Error "<context>: CHOLMOD could not factorise
  // the <what> matrix ..." when A is not positive definite. `poll` (support/progress.h), when set, is polled
  // every 20 ms while CHOLMOD works on a thread of its own (neither its ordering nor its numeric factorisation
  // can be interrupted inside): a stop is answered at once, and the abandoned factorisation finishes in the
  // background and is freed. Whatever the poll throws leaves this object as it was.
  void factorize(const Eigen::SparseMatrix<double>& A, const std::string& context, const std::string& what,
                 const ProgressFn& poll = {});
  // B (n × k, row-major) is overwritten by A⁻¹ B. `work` is scratch of the same size.
  void solve(Block& B, Block& work) const;
  Index size() const { return n_; }
  Index factor_nonzeros() const { return static_cast<Index>(value_.size()); }
  // "cholmod" or "eigen-llt": which factorisation is used.
  static std::string backend();

 private:
  Index n_ = 0;
  std::vector<int> colptr_, row_;  // L in compressed columns, diagonal first in each column
  std::vector<double> value_;
  std::vector<int> perm_;  // row k of the factorised system is row perm_[k] of A
};

}  // namespace cshapes
