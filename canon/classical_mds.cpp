#include "cshapes/canon/classical_mds.h"

#include <Spectra/SymEigsSolver.h>
#include <omp.h>

#include <Eigen/Eigenvalues>

#include <cmath>
#include <limits>
#include <mutex>
#include <string>
#include <utility>
#include <vector>

#include "cshapes/support/error.h"
#include "cshapes/support/serial_eigen_products.h"
#include "cshapes/support/simd.h"
#include "cshapes/support/timing.h"

namespace cshapes {
namespace {

// Tile edge of the product's pass over D (column sums of a tile stay in L1).
constexpr Index kTile = 256;

// First pass over D: validity, and the sums behind tr B and ‖B‖²_F.
struct SquaredDistanceSums {
  Eigen::VectorXd row_sums;  // Rᵢ = Σⱼ Dᵢⱼ²
  double sum_fourth = 0;     // Σᵢⱼ Dᵢⱼ⁴
  double diagonal = 0;       // Σᵢ Dᵢᵢ² (zero for a proper distance matrix)
};

template <typename Scalar>
SquaredDistanceSums squared_distance_sums(const Eigen::Matrix<Scalar, Eigen::Dynamic, Eigen::Dynamic>& D) {
  const Index n = D.rows();
  SquaredDistanceSums s;
  s.row_sums.resize(n);
  Index bad_row = -1;
  Eigen::VectorXd row_fourth(n);  // summed in row order below: deterministic, unlike an OpenMP reduction
#pragma omp parallel for schedule(static)
  for (Index i = 0; i < n; ++i) {
    const Scalar* column = D.data() + i * n;
    double row = 0, fourth = 0;
    bool finite = true;
#pragma omp simd reduction(+ : row, fourth) reduction(&& : finite)
    for (Index j = 0; j < n; ++j) {
      double a = static_cast<double>(column[j]) * static_cast<double>(column[j]);
      row += a;
      fourth += a * a;
      finite = finite && column[j] >= 0 && column[j] <= std::numeric_limits<Scalar>::max();
    }
    s.row_sums[i] = row;
    row_fourth[i] = fourth;
    if (!finite) {
#pragma omp critical(cshapes_cmds_bad_row)
      if (bad_row < 0 || i < bad_row) bad_row = i;
    }
  }
  if (bad_row >= 0) {
    Index j = 0;
    while (j < n && D(j, bad_row) >= 0 && D(j, bad_row) <= std::numeric_limits<Scalar>::max()) ++j;
    fail("classical MDS: distance (", bad_row, ", ", j, ") is ", static_cast<double>(D(j, bad_row)),
         "; distances must be finite and non-negative", bad_distance_hint(D, j, bad_row));
  }
  double sum_fourth = 0;
  for (Index i = 0; i < n; ++i) sum_fourth += row_fourth[i];
  s.sum_fourth = sum_fourth;
  for (Index i = 0; i < n; ++i) s.diagonal += static_cast<double>(D(i, i)) * static_cast<double>(D(i, i));
  return s;
}

namespace baseline {
#include "cshapes/canon/classical_mds_simd.inl"
}  // namespace baseline
#pragma GCC push_options
#pragma GCC target("avx2,fma")
#pragma GCC optimize("fp-contract=off")
namespace avx2 {
#include "cshapes/canon/classical_mds_simd.inl"
}  // namespace avx2
#pragma GCC pop_options
#pragma GCC push_options
#pragma GCC target("avx2,fma,avx512f,avx512vl,avx512dq,avx512bw")
#pragma GCC optimize("fp-contract=off")
namespace avx512 {
#include "cshapes/canon/classical_mds_simd.inl"
}  // namespace avx512
#pragma GCC pop_options

// row_pass of the kernels' instruction set (the same bytes on each).
template <typename Entry>
double row_pass_kernel(SimdTarget target, const Entry* column, const double* v, double vi, Index ja, Index j1,
                       double* sums) {
  switch (target) {
    case SimdTarget::Avx512:
      return avx512::row_pass(column, v, vi, ja, j1, sums);
    case SimdTarget::Avx2:
      return avx2::row_pass(column, v, vi, ja, j1, sums);
    case SimdTarget::Baseline:
      break;
  }
  return baseline::row_pass(column, v, vi, ja, j1, sums);
}

// (B + sI)·v = −½ J (D∘D) J v + s v without forming B: centre v, one pass y = (D∘D) v over columns (= rows),
// centre y. The shift s ≈ ‖B‖_F leaves the Krylov spaces (and so Lanczos' iterates) unchanged but makes
// Spectra's test, relative to each |eigenvalue|, an absolute one at the scale of B: without it a near-zero
// third eigenvalue (a flat shape) takes hundreds of products to pin down to a relative accuracy it does not
// need. The product is also multiplied by a power of two (exact) that brings ‖B‖_F to about 1: Spectra's
// test has an absolute floor (ε^{2/3} ≈ 4e-11 of each |eigenvalue|), so a mesh scaled by 1e-9 (‖B‖ ≈ 1e-18)
// "converged" at once to a form 17% off. Lanczos' unit vectors are unchanged by the exact scaling.
template <typename Entry>
class DoubleCentredOp {
 public:
  using Scalar = double;  // Spectra requires this name

  DoubleCentredOp(const Eigen::Matrix<Entry, Eigen::Dynamic, Eigen::Dynamic>& D, double shift,
                  const ProgressFn& progress)
      : D_(D), shift_(shift), scale_(unit_scale(shift)), progress_(progress), centred_(D.rows()) {
    const Index n = D.rows(), blocks = (n + kTile - 1) / kTile;
    for (Index bj = 0; bj < blocks; ++bj)
      for (Index bi = 0; bi <= bj; ++bi) tiles_.emplace_back(bi, bj);
  }
  Index rows() const { return D_.rows(); }
  Index cols() const { return D_.rows(); }

  void perform_op(const double* x_in, double* y_out) const {
    const Index n = D_.rows();
    Eigen::Map<const Eigen::VectorXd> x(x_in, n);
    centred_ = x.array() - x.mean();
    const double* v = centred_.data();
    // Symmetry: only the tiles above the diagonal are read, each entry credited to its row and its column,
    // so a product streams half of D. Bit-identical for any thread count (as SMACOF and Coulomb are): each
    // tile writes its row and column sums to slots of its own, and each block of the product adds its
    // tiles' slots in one fixed order.
    const Index blocks = (n + kTile - 1) / kTile;
    tile_rows_.resize(tiles_.size() * kTile);
    tile_columns_.resize(tiles_.size() * kTile);
    const SimdTarget target = simd_target();
#pragma omp parallel for schedule(dynamic, 1)
    for (size_t t = 0; t < tiles_.size(); ++t) {
      const Index i0 = tiles_[t].first * kTile, i1 = std::min(n, i0 + kTile);
      const Index j0 = tiles_[t].second * kTile, j1 = std::min(n, j0 + kTile);
      double* row_sums = tile_rows_.data() + t * kTile;
      double* column_sums = tile_columns_.data() + t * kTile;
      std::fill(row_sums, row_sums + kTile, 0.0);
      std::fill(column_sums, column_sums + kTile, 0.0);
      for (Index i = i0; i < i1; ++i) {
        const Index ja = std::max(j0, i + 1);
        if (ja >= j1) continue;
        if (i + 2 < i1) {  // the row two ahead: each tile row is a separate short run of D
          const char* next = reinterpret_cast<const char*>(D_.data() + (i + 2) * n + std::max(j0, i + 3));
          const char* end = reinterpret_cast<const char*>(D_.data() + (i + 2) * n + j1);
          for (; next < end; next += 64) __builtin_prefetch(next, 0, 3);
        }
        const Entry* column = D_.data() + i * n;  // column i = row i
        double* sums = column_sums - j0;
        row_sums[i - i0] = row_pass_kernel(target, column, v, v[i], ja, j1, sums);
      }
    }
    // Block b of the product: its row sums from tiles (b, b..), then its column sums from tiles (..b, b).
    Eigen::VectorXd product(n);
    auto tile_index = [](Index bi, Index bj) { return static_cast<size_t>(bj * (bj + 1) / 2 + bi); };
#pragma omp parallel for schedule(static)
    for (Index b = 0; b < blocks; ++b) {
      const Index i0 = b * kTile, i1 = std::min(n, i0 + kTile);
      for (Index i = i0; i < i1; ++i) product[i] = 0;
      for (Index bj = b; bj < blocks; ++bj) {
        const double* row_sums = tile_rows_.data() + tile_index(b, bj) * kTile;
        for (Index i = i0; i < i1; ++i) product[i] += row_sums[i - i0];
      }
      for (Index bi = 0; bi <= b; ++bi) {
        const double* column_sums = tile_columns_.data() + tile_index(bi, b) * kTile;
        for (Index i = i0; i < i1; ++i) product[i] += column_sums[i - i0];
      }
    }
    for (Index i = 0; i < n; ++i) {  // the diagonal (zero for a proper distance matrix)
      const double d = static_cast<double>(D_(i, i));
      product[i] += d * d * v[i];
    }
    std::copy(product.data(), product.data() + n, y_out);
    Eigen::Map<Eigen::VectorXd> y(y_out, n);
    y = scale_ * (-0.5 * (y.array() - y.mean()) + shift_ * x.array());
    ++products_;
    if (progress_) progress_("classical mds", products_, 0);
  }
  int products() const {
    return products_;
  }
  // The factor of every product: Spectra's eigenvalues are scale() × (λ + shift).
  double scale() const { return scale_; }

 private:
  // The power of two 2^-e with 2^-e · norm in [0.5, 1); 1 for a zero or non-finite norm.
  static double unit_scale(double norm) {
    if (!(norm > 0) || !std::isfinite(norm)) return 1;
    int exponent = 0;
    std::frexp(norm, &exponent);
    return std::ldexp(1.0, -exponent);
  }

  const Eigen::Matrix<Entry, Eigen::Dynamic, Eigen::Dynamic>& D_;
  double shift_;
  double scale_;
  const ProgressFn& progress_;
  mutable Eigen::VectorXd centred_;
  std::vector<std::pair<Index, Index>> tiles_;  // upper-triangle tiles (row block ≤ column block)
  // Per tile, its rows' and its columns' sums of one product (kTile each): 2n²/kTile doubles in all.
  mutable std::vector<double> tile_rows_, tile_columns_;
  mutable int products_ = 0;
};

template <typename Scalar>
ClassicalMdsResult classical_mds_impl(const Eigen::Matrix<Scalar, Eigen::Dynamic, Eigen::Dynamic>& D,
                                      const ClassicalMdsOptions& options) {
  const WallClock::time_point start = WallClock::now();
  const Index n = D.rows();
  CSHAPES_REQUIRE(D.rows() == D.cols(), "classical MDS: distance matrix must be square, got ", D.rows(), "x",
                  D.cols());
  CSHAPES_REQUIRE(n >= 4, "classical MDS: needs at least 4 points for a 3-D embedding, got ", n);
  CSHAPES_REQUIRE(options.lanczos_vectors >= 7, "classical MDS: lanczos_vectors must be at least 7, got ",
                  options.lanczos_vectors);

  SquaredDistanceSums sums = squared_distance_sums(D);
  ClassicalMdsResult result;
  const double nd = static_cast<double>(n);
  const double total = sums.row_sums.sum();
  // tr B = −½ tr(J A J) = −½ (tr A − 1ᵀA1 / n), with A = D∘D.
  result.trace = -0.5 * (sums.diagonal - total / nd);
  // ‖J A J‖²_F = ‖A‖²_F − (2/n) ‖A1‖² + (1ᵀA1)² / n² for symmetric A.
  result.frobenius_squared =
      0.25 * (sums.sum_fourth - 2.0 / nd * sums.row_sums.squaredNorm() + total * total / (nd * nd));

  Eigen::Vector3d top_values;
  Eigen::MatrixXd top_vectors;  // n×3
  if (n < options.dense_below) {
    // B = −½ J A J formed from the upper triangle (as the products read it), all eigenpairs at once.
    Eigen::MatrixXd B(n, n);
    for (Index j = 0; j < n; ++j)
      for (Index i = 0; i <= j; ++i) {
        const double d = static_cast<double>(D(i, j));
        B(i, j) = B(j, i) = d * d;
      }
    // Bᵢⱼ = −½ (Aᵢⱼ − mᵢ − mⱼ + m̄) with m the column means of A (= row means) and m̄ their mean.
    const Eigen::RowVectorXd means = B.colwise().mean();
    const double grand_mean = means.mean();
    B = (-0.5 * ((B.rowwise() - means).colwise() - means.transpose()).array() - 0.5 * grand_mean).matrix();
    Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> solver(B);
    if (solver.info() != Eigen::Success)
      fail("classical MDS: the dense eigendecomposition of B failed (n = ", n, ")");
    const Eigen::VectorXd& values = solver.eigenvalues();  // ascending
    top_values = values.tail(3).reverse();
    top_vectors = solver.eigenvectors().rightCols(3).rowwise().reverse();
    result.most_negative_eigenvalue =
        options.most_negative_eigenvalue ? values[0] : std::numeric_limits<double>::quiet_NaN();
  } else {
    const double shift = std::sqrt(std::max(0.0, result.frobenius_squared));
    DoubleCentredOp<Scalar> op(D, shift, options.progress);
    const Index ncv = std::min<Index>(options.lanczos_vectors, n);
    // One Lanczos run for both ends when λ_min is wanted: 3 from the top and 2 from the bottom share the
    // Krylov space, far cheaper than a second run.
    const bool both_ends = options.most_negative_eigenvalue && n >= 8;
    const Index nev = both_ends ? 5 : 3;
    const SerialEigenProducts serial_eigen_products;
    Spectra::SymEigsSolver<DoubleCentredOp<Scalar>> eigs(op, nev, std::max<Index>(ncv, 2 * nev + 1));
    eigs.init();
    eigs.compute(both_ends ? Spectra::SortRule::BothEnds : Spectra::SortRule::LargestAlge,
                 options.max_restarts, options.tolerance, Spectra::SortRule::LargestAlge);
    if (eigs.info() != Spectra::CompInfo::Successful)
      fail("classical MDS: the Lanczos iteration did not converge in ", options.max_restarts,
           " restarts (raise lanczos_vectors or the tolerance)");
    const Eigen::VectorXd values = eigs.eigenvalues().array() / op.scale() - shift;  // descending
    const Eigen::MatrixXd vectors = eigs.eigenvectors();
    top_values = values.head(3);
    top_vectors = vectors.leftCols(3);
    result.most_negative_eigenvalue = both_ends ? values[nev - 1] : std::numeric_limits<double>::quiet_NaN();
    result.matrix_products = op.products();
  }
  result.eigenvalues = top_values;
  result.X.resize(n, 3);
  for (int k = 0; k < 3; ++k)
    result.X.col(k) = top_vectors.col(k) * std::sqrt(std::max(0.0, result.eigenvalues[k]));
  result.X.rowwise() -= result.X.colwise().mean();
  const double top_sum = result.eigenvalues.sum();
  const double top_energy = result.eigenvalues.squaredNorm();
  result.explained_energy =
      result.frobenius_squared > 0 ? std::min(1.0, top_energy / result.frobenius_squared) : 1;
  result.negative_energy_upper_bound = 1 - result.explained_energy;
  result.negative_mass_lower_bound = top_sum > 0 ? std::max(0.0, top_sum - result.trace) / top_sum : 0;
  result.seconds = seconds_since(start);
  return result;
}

}  // namespace

ClassicalMdsResult classical_mds(const DistanceMatrix& D, const ClassicalMdsOptions& options) {
  return classical_mds_impl<float>(D, options);
}

ClassicalMdsResult classical_mds(const Eigen::MatrixXd& D, const ClassicalMdsOptions& options) {
  return classical_mds_impl<double>(D, options);
}

}  // namespace cshapes
