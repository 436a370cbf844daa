#include "cshapes/canon/spectral_mds.h"

#include <Eigen/Eigenvalues>
#include <Eigen/QR>

#include "cshapes/support/error.h"
#include "cshapes/support/serial_eigen_products.h"

namespace cshapes {

SpectralMdsResult spectral_mds(const LaplaceBeltramiEigen& eigen, const std::vector<int>& sources,
                               const Eigen::MatrixXf& rows) {
  const SerialEigenProducts serial_eigen_products;  // bit-identical for any thread count
  const Index n = eigen.vectors.rows(), k = eigen.vectors.cols(), L = static_cast<Index>(sources.size());
  CSHAPES_REQUIRE(k >= 4, "spectral MDS: needs at least 4 eigenpairs, got ", k);
  CSHAPES_REQUIRE(rows.rows() == L && rows.cols() == n, "spectral MDS: ", rows.rows(), " × ", rows.cols(),
                  " geodesic rows for ", L, " sources and ", n, " vertices");
  CSHAPES_REQUIRE(L >= k, "spectral MDS: ", L, " sources for ", k,
                  " eigenpairs (the fit needs at least as many sources)");
  const Eigen::MatrixXd& Phi = eigen.vectors;
  Eigen::MatrixXd PhiS(L, k);
  for (Index s = 0; s < L; ++s) PhiS.row(s) = Phi.row(sources[static_cast<size_t>(s)]);
  const Eigen::MatrixXd D2 = rows.cast<double>().array().square().matrix();  // L × n
  // Columns: the M-weighted projection onto the basis (exact for M-orthonormal Φ); rows: least squares.
  const Eigen::MatrixXd projected = D2 * eigen.mass.asDiagonal() * Phi;  // L × k
  Eigen::MatrixXd alpha = PhiS.completeOrthogonalDecomposition().solve(projected);
  alpha = 0.5 * (alpha + alpha.transpose()).eval();
  SpectralMdsResult r;
  {
    const Eigen::MatrixXd fitted = PhiS * alpha * Phi.transpose();
    const Eigen::VectorXd w = eigen.mass;
    const double miss = ((fitted - D2).array().square().rowwise() * w.transpose().array()).sum();
    const double all = (D2.array().square().rowwise() * w.transpose().array()).sum();
    r.fit_residual = all > 0 ? std::sqrt(miss / all) : 0;
  }
  // Area-weighted double centring removes φ_0 (constant; every other φ_i is M-orthogonal to it).
  const Eigen::MatrixXd B = -0.5 * alpha.bottomRightCorner(k - 1, k - 1);
  Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> solver(B);
  CSHAPES_REQUIRE(solver.info() == Eigen::Success, "spectral MDS: the eigensolver failed");
  const Eigen::VectorXd mu = solver.eigenvalues();  // increasing
  r.X = Points::Zero(n, 3);
  double negative = 0, total = 0;
  for (Index i = 0; i < mu.size(); ++i) {
    total += std::abs(mu[i]);
    if (mu[i] < 0) negative -= mu[i];
  }
  r.negative_mass = total > 0 ? negative / total : 0;
  for (int c = 0; c < 3; ++c) {
    const Index i = mu.size() - 1 - c;
    r.eigenvalues[c] = mu[i];
    const double scale = std::sqrt(std::max(0.0, mu[i]));
    r.X.col(c) = Phi.rightCols(k - 1) * solver.eigenvectors().col(i) * scale;
  }
  return r;
}

}  // namespace cshapes
