#include "canon/classical_mds.h"

#include <Spectra/SymEigsSolver.h>

#include <chrono>
#include <cmath>
#include <limits>

#include "core/error.h"

namespace cshapes {
namespace {

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
  double sum_fourth = 0;
#pragma omp parallel for schedule(static) reduction(+ : sum_fourth)
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
    sum_fourth += fourth;
    if (!finite) {
#pragma omp critical(cshapes_cmds_bad_row)
      if (bad_row < 0 || i < bad_row) bad_row = i;
    }
  }
  if (bad_row >= 0) {
    Index j = 0;
    while (j < n && D(j, bad_row) >= 0 && D(j, bad_row) <= std::numeric_limits<Scalar>::max()) ++j;
    fail("classical MDS: distance (", bad_row, ", ", j, ") is ", D(j, bad_row),
         "; distances must be finite and non-negative (an infinite distance means a disconnected mesh: "
         "keep its largest component)");
  }
  s.sum_fourth = sum_fourth;
  for (Index i = 0; i < n; ++i) s.diagonal += static_cast<double>(D(i, i)) * static_cast<double>(D(i, i));
  return s;
}

// B·v = −½ J (D∘D) J v without forming B: centre v, one pass y = (D∘D) v over columns (= rows), centre y.
template <typename Entry>
class DoubleCentredOp {
 public:
  using Scalar = double;  // Spectra requires this name

  DoubleCentredOp(const Eigen::Matrix<Entry, Eigen::Dynamic, Eigen::Dynamic>& D, const ProgressFn& progress)
      : D_(D), progress_(progress), centred_(D.rows()) {}
  Index rows() const { return D_.rows(); }
  Index cols() const { return D_.rows(); }

  void perform_op(const double* x_in, double* y_out) const {
    const Index n = D_.rows();
    Eigen::Map<const Eigen::VectorXd> x(x_in, n);
    centred_ = x.array() - x.mean();
    const double* v = centred_.data();
#pragma omp parallel for schedule(static)
    for (Index i = 0; i < n; ++i) {
      const Entry* column = D_.data() + i * n;
      double sum = 0;
#pragma omp simd reduction(+ : sum)
      for (Index j = 0; j < n; ++j) {
        double d = static_cast<double>(column[j]);
        sum += d * d * v[j];
      }
      y_out[i] = sum;
    }
    Eigen::Map<Eigen::VectorXd> y(y_out, n);
    y = -0.5 * (y.array() - y.mean());
    ++products_;
    if (progress_) progress_("classical mds", products_, 0);
  }
  int products() const { return products_; }

 private:
  const Eigen::Matrix<Entry, Eigen::Dynamic, Eigen::Dynamic>& D_;
  const ProgressFn& progress_;
  mutable Eigen::VectorXd centred_;
  mutable int products_ = 0;
};

template <typename Scalar>
ClassicalMdsResult classical_mds_impl(const Eigen::Matrix<Scalar, Eigen::Dynamic, Eigen::Dynamic>& D,
                                      const ClassicalMdsOptions& options) {
  auto start = std::chrono::steady_clock::now();
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

  DoubleCentredOp<Scalar> op(D, options.progress);
  const Index ncv = std::min<Index>(options.lanczos_vectors, n);
  {
    Spectra::SymEigsSolver<DoubleCentredOp<Scalar>> eigs(op, 3, ncv);
    eigs.init();
    eigs.compute(Spectra::SortRule::LargestAlge, options.max_restarts, options.tolerance,
                 Spectra::SortRule::LargestAlge);
    if (eigs.info() != Spectra::CompInfo::Successful)
      fail("classical MDS: the Lanczos iteration did not converge in ", options.max_restarts,
           " restarts (raise lanczos_vectors or the tolerance)");
    result.eigenvalues = eigs.eigenvalues();
    Eigen::MatrixXd vectors = eigs.eigenvectors();
    result.X.resize(n, 3);
    for (int k = 0; k < 3; ++k)
      result.X.col(k) = vectors.col(k) * std::sqrt(std::max(0.0, result.eigenvalues[k]));
    result.X.rowwise() -= result.X.colwise().mean();
  }
  result.most_negative_eigenvalue = std::numeric_limits<double>::quiet_NaN();
  if (options.most_negative_eigenvalue) {
    Spectra::SymEigsSolver<DoubleCentredOp<Scalar>> eigs(op, 1, ncv);
    eigs.init();
    eigs.compute(Spectra::SortRule::SmallestAlge, options.max_restarts, options.tolerance,
                 Spectra::SortRule::SmallestAlge);
    if (eigs.info() == Spectra::CompInfo::Successful) result.most_negative_eigenvalue = eigs.eigenvalues()[0];
  }
  const double top_sum = result.eigenvalues.sum();
  const double top_energy = result.eigenvalues.squaredNorm();
  result.explained_energy = result.frobenius_squared > 0 ? std::min(1.0, top_energy / result.frobenius_squared) : 1;
  result.negative_energy_upper_bound = 1 - result.explained_energy;
  result.negative_mass_lower_bound = top_sum > 0 ? std::max(0.0, top_sum - result.trace) / top_sum : 0;
  result.matrix_products = op.products();
  result.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
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
