#include "cshapes/operators/laplace_beltrami.h"

#include <Eigen/Eigenvalues>
#include <Spectra/SymEigsShiftSolver.h>
#include <algorithm>
#include <cmath>
#include <sstream>

#include "cshapes/operators/cotangent_operator.h"
#include "cshapes/support/error.h"
#include "cshapes/support/serial_eigen_products.h"
#include "cshapes/operators/intrinsic_delaunay.h"
#include "cshapes/operators/sparse_cholesky.h"
#include "cshapes/support/timing.h"

namespace cshapes {

namespace {

using SparseMatrix = Eigen::SparseMatrix<double>;
using Triplets = std::vector<Eigen::Triplet<double>>;

constexpr Index kLanczosExtra = 6;  // eigenpairs computed beyond the wanted ones (see below)

// The shifted inverse of the symmetric form, y = M^{1/2} (L − σM)^{-1} M^{1/2} x, for Spectra: its
// eigenvalues are 1/(λ − σ), so the largest are the λ nearest σ (the smallest, σ < 0).
// Spectra sees it times a power of two c (exact), as the shift-invert of L/c at σ/c: λ ∝ 1/scale², and
// Spectra's convergence test has an absolute floor (ε^{2/3} of each |1/(λ − σ)|), so a mesh scaled by 1e9
// (1/(λ − σ) ≈ 1e18) converged to a form 10% off. With c ≈ |σ| the largest value is about 1 at any scale;
// Spectra's eigenvalues are then λ/c (scale_eigenvalue() brings them back).
class ShiftInvertOp {
 public:
  using Scalar = double;  // Spectra requires this name
  ShiftInvertOp(const SparseMatrix& L, const Eigen::VectorXd& mass, std::string what, double scale,
                const ProgressFn& progress)
      : L_(L), sqrt_mass_(mass.cwiseSqrt()), what_(std::move(what)), scale_(scale), progress_(progress) {}
  Index rows() const { return L_.rows(); }
  Index cols() const { return L_.rows(); }
  // sigma: Spectra's shift, of L/c.
  void set_shift(double sigma) {
    SparseMatrix A = L_;
    const double shift = scale_ * sigma;  // exact: the σ given to Spectra was σ/c
    for (Index i = 0; i < A.rows(); ++i) A.coeffRef(i, i) -= shift * sqrt_mass_[i] * sqrt_mass_[i];
    cholesky_.factorize(A, what_, "shifted Laplacian (L - sigma M)", progress_);
  }
  void perform_op(const double* x_in, double* y_out) const {
    if (progress_) progress_("", 0, 0);  // a poll: a stop ends Spectra's iteration by the exception
    const Index n = rows();
    block_.resize(n, 1);
    for (Index i = 0; i < n; ++i) block_(i, 0) = sqrt_mass_[i] * x_in[i];
    cholesky_.solve(block_, work_);
    for (Index i = 0; i < n; ++i) y_out[i] = scale_ * (sqrt_mass_[i] * block_(i, 0));
    ++products_;
  }
  // The power of two nearest |sigma| (1 for 0 or non-finite): the c above.
  static double scale_for(double sigma) {
    if (!(std::abs(sigma) > 0) || !std::isfinite(sigma)) return 1;
    int exponent = 0;
    std::frexp(std::abs(sigma), &exponent);
    return std::ldexp(1.0, exponent);
  }
  Index products() const { return products_; }

 private:
  const SparseMatrix& L_;
  Eigen::VectorXd sqrt_mass_;
  std::string what_;
  double scale_;
  const ProgressFn& progress_;
  SparseCholesky cholesky_;
  mutable SparseCholesky::Block block_, work_;
  mutable Index products_ = 0;
};

// Vertices without mass (in no face, or isolated points) would make M singular: they get a tiny mass and a
// stiffness tying them to nothing, so their eigenvalues are huge and never among the smallest.
void guard_massless(LaplacianMatrices& A) {
  const Index n = A.mass.size();
  double min_mass = std::numeric_limits<double>::infinity(), max_diag = 0;
  for (Index i = 0; i < n; ++i)
    if (A.mass[i] > 0) min_mass = std::min(min_mass, A.mass[i]);
  for (Index i = 0; i < n; ++i) max_diag = std::max(max_diag, A.L.coeff(i, i) / std::max(A.mass[i], 1e-300));
  bool any = false;
  for (Index i = 0; i < n; ++i) any = any || !(A.mass[i] > 0);
  if (!any) return;
  CSHAPES_REQUIRE(std::isfinite(min_mass), "Laplace-Beltrami: no vertex has mass (no faces, no edges)");
  for (Index i = 0; i < n; ++i) {
    if (A.mass[i] > 0) continue;
    A.mass[i] = min_mass;
    A.L.coeffRef(i, i) += 1e3 * max_diag * min_mass;
  }
}

void make_signs_deterministic(Eigen::MatrixXd& vectors) {
  for (Index c = 0; c < vectors.cols(); ++c) {
    Index at = 0;
    vectors.col(c).cwiseAbs().maxCoeff(&at);
    if (vectors(at, c) < 0) vectors.col(c) *= -1;
  }
}

void finish(LaplaceBeltramiEigen& e, const LaplacianMatrices& A, const LaplaceBeltramiOptions& options) {
  make_signs_deterministic(e.vectors);
  e.mass = A.mass;
  e.area = A.mass.sum();
  e.laplacian = A.kind;
  e.flips = A.flips;
  e.near_multiple = near_multiple_groups(e.values, options.near_multiple_gap);
}

}  // namespace

LaplacianMatrices cotangent_laplacian(const Mesh& mesh, bool intrinsic_delaunay_triangulation, const ProgressFn& poll) {
  const Index n = mesh.num_vertices(), m = mesh.num_faces();
  CSHAPES_REQUIRE(m > 0, "cotangent Laplacian: the mesh has no faces (a point cloud: use the kNN graph)");
  report_progress_in_parallel(poll, "", 0, 0);
  const IntrinsicTriangulation T =
      intrinsic_delaunay_triangulation ? intrinsic_delaunay(mesh) : intrinsic_triangulation(mesh);
  report_progress_in_parallel(poll, "", 0, 0);
  LaplacianMatrices out;
  out.kind = intrinsic_delaunay_triangulation ? "intrinsic-delaunay" : "cotangent";
  out.flips = T.flips;
  out.mollification = T.mollification;
  CotangentOperator op = cotangent_operator(T, n);
  out.L = std::move(op.L);
  out.mass = std::move(op.mass);
  return out;
}

LaplacianMatrices knn_graph_laplacian(const Points& P, const KnnGraphOptions& knn) {
  const Index n = P.rows();
  CSHAPES_REQUIRE(n >= 2, "kNN graph Laplacian: needs at least 2 points, got ", n);
  const Edges E = knn_graph(P, knn);
  Eigen::VectorXd d2(E.rows());
  for (Index e = 0; e < E.rows(); ++e) d2[e] = (P.row(E(e, 0)) - P.row(E(e, 1))).squaredNorm();
  const double eps = d2.size() ? d2.mean() : 0;
  CSHAPES_REQUIRE(eps > 0, "kNN graph Laplacian: all points coincide");
  Eigen::VectorXd w = (-d2.array() / eps).exp();
  // α = 1 (Coifman & Lafon): divide out the sampling density q_i (kernel sum, the point itself included).
  Eigen::VectorXd q = Eigen::VectorXd::Ones(n);
  for (Index e = 0; e < E.rows(); ++e) {
    q[E(e, 0)] += w[e];
    q[E(e, 1)] += w[e];
  }
  LaplacianMatrices out;
  out.kind = "knn-graph";
  out.mass = Eigen::VectorXd::Zero(n);
  Triplets entries;
  entries.reserve(4 * E.rows());
  double weight_sum = 0, moment_sum = 0;
  for (Index e = 0; e < E.rows(); ++e) {
    const int i = E(e, 0), j = E(e, 1);
    const double wt = w[e] / (q[i] * q[j]);
    weight_sum += wt;
    moment_sum += wt * d2[e];
    out.mass[i] += wt;
    out.mass[j] += wt;
    entries.emplace_back(i, j, -wt);
    entries.emplace_back(j, i, -wt);
    entries.emplace_back(i, i, wt);
    entries.emplace_back(j, j, wt);
  }
  // L φ = λ D̃ φ has the random walk's eigenvalues 1 − μ, and on a surface (P f − f)(x) ≈ (m₂/4) Δf with m₂
  // the kernel's mean squared step (a 2-D second moment): M = D̃ m₂/4 puts λ in 1/length² (see header).
  out.mass *= moment_sum / weight_sum / 4;
  out.L.resize(n, n);
  out.L.setFromTriplets(entries.begin(), entries.end());
  return out;
}

LaplacianMatrices laplace_beltrami_matrices(const Mesh& mesh, const LaplaceBeltramiOptions& options,
                                            const KnnGraphOptions& knn) {
  return mesh.is_point_cloud() ? knn_graph_laplacian(mesh.V, knn)
                               : cotangent_laplacian(mesh, options.intrinsic_delaunay, polls_of(options.progress));
}

LaplaceBeltramiEigen laplace_beltrami_eigen_dense(const LaplacianMatrices& matrices,
                                                  const LaplaceBeltramiOptions& options) {
  const SerialEigenProducts serial_eigen_products;  // bit-identical for any thread count
  auto start = WallClock::now();
  LaplacianMatrices A = matrices;
  guard_massless(A);
  // The symmetric form M^{-1/2} L M^{-1/2} (M diagonal), then φ = M^{-1/2} ψ.
  const Eigen::VectorXd inv_sqrt = A.mass.cwiseSqrt().cwiseInverse();
  const Eigen::MatrixXd S = inv_sqrt.asDiagonal() * Eigen::MatrixXd(A.L) * inv_sqrt.asDiagonal();
  Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> solver(0.5 * (S + S.transpose()));
  CSHAPES_REQUIRE(solver.info() == Eigen::Success, "Laplace-Beltrami: the dense eigensolver failed");
  LaplaceBeltramiEigen e;
  e.values = solver.eigenvalues();
  e.vectors = inv_sqrt.asDiagonal() * solver.eigenvectors();
  e.solver = "dense";
  finish(e, A, options);
  e.mass = matrices.mass;
  e.seconds = seconds_since(start);
  return e;
}

LaplaceBeltramiEigen laplace_beltrami_eigen(const LaplacianMatrices& matrices,
                                            const LaplaceBeltramiOptions& options, const std::string& what) {
  const Index n = matrices.L.rows(), k = options.eigenpairs;
  CSHAPES_REQUIRE(k >= 1 && k < n, what, ": ", k, " eigenpairs asked of ", n, " vertices (at most ", n - 1,
                  ")");
  // Lanczos with one start vector finds the copies of a multiple eigenvalue only through rounding, and may
  // stop before the last copy of a group at the end of the wanted range (a 642-vertex icosphere lost one of
  // four at λ ≈ 11.8 when asked for exactly 16): so it is asked for kLanczosExtra more than wanted, and a
  // subspace of twice that.
  const Index nev = k + std::max<Index>(kLanczosExtra, k / 2);
  const Index ncv = std::min<Index>(n, 2 * nev + 1);
  if (n <= kDenseEigenVertices || ncv >= n) {
    LaplaceBeltramiEigen e = laplace_beltrami_eigen_dense(matrices, options);
    e.values.conservativeResize(k);
    e.vectors.conservativeResize(n, k);
    e.near_multiple = near_multiple_groups(e.values, options.near_multiple_gap);
    return e;
  }
  const SerialEigenProducts serial_eigen_products;  // Spectra's restarts: bit-identical for any thread count
  report_progress_in_parallel(options.progress, "", 0, 0);  // a poll: the matrices took their time
  auto start = WallClock::now();
  LaplacianMatrices A = matrices;
  guard_massless(A);
  double mean_ratio = 0;
  for (Index i = 0; i < n; ++i) mean_ratio += A.L.coeff(i, i) / A.mass[i];
  mean_ratio /= n;
  const double sigma = -kShiftFactor * mean_ratio / n;
  const double scale = ShiftInvertOp::scale_for(sigma);
  ShiftInvertOp op(A.L, A.mass, what, scale, options.progress);
  Spectra::SymEigsShiftSolver<ShiftInvertOp> eigs(op, nev, ncv, sigma / scale);
  eigs.init();
  // Selection by the transformed values 1/(λ − σ), largest first; sorted back to increasing λ.
  eigs.compute(Spectra::SortRule::LargestMagn, 1000, 1e-10, Spectra::SortRule::SmallestAlge);
  CSHAPES_REQUIRE(eigs.info() == Spectra::CompInfo::Successful, what,
                  ": shift-invert Lanczos did not converge (", k, " eigenpairs, ", n, " vertices)");
  LaplaceBeltramiEigen e;
  e.values = scale * eigs.eigenvalues().head(k);
  e.vectors = A.mass.cwiseSqrt().cwiseInverse().asDiagonal() * eigs.eigenvectors().leftCols(k);
  e.solver = "shift-invert lanczos (" + SparseCholesky::backend() + ")";
  e.operator_products = op.products();
  finish(e, A, options);
  e.mass = matrices.mass;
  e.seconds = seconds_since(start);
  return e;
}

LaplaceBeltramiEigen laplace_beltrami_eigen(const Mesh& mesh, const LaplaceBeltramiOptions& options,
                                            const KnnGraphOptions& knn) {
  return laplace_beltrami_eigen(laplace_beltrami_matrices(mesh, options, knn), options);
}

std::vector<std::vector<int>> near_multiple_groups(const Eigen::VectorXd& values, double gap) {
  std::vector<std::vector<int>> groups;
  if (values.size() == 0) return groups;
  // Below this, eigenvalues count as zero (several components): rounding of the factorisation.
  const double zero = 1e-9 * values.cwiseAbs().maxCoeff();
  for (Index i = 0; i + 1 < values.size(); ++i) {
    const double a = values[i], b = values[i + 1];
    const bool both_zero = std::abs(a) <= zero && std::abs(b) <= zero;
    const bool close = both_zero || (std::abs(b) > zero && b - a <= gap * std::abs(b));
    if (!close) continue;
    if (groups.empty() || groups.back().back() != i) groups.push_back({static_cast<int>(i)});
    groups.back().push_back(static_cast<int>(i + 1));
  }
  return groups;
}

std::string near_multiple_description(const LaplaceBeltramiEigen& eigen) {
  if (eigen.near_multiple.empty()) return "";
  std::ostringstream s;
  s.precision(6);
  s << "near-multiple eigenvalues:";
  for (size_t g = 0; g < eigen.near_multiple.size(); ++g) {
    const std::vector<int>& group = eigen.near_multiple[g];
    s << (g ? ";" : "") << " λ" << group.front() << "..λ" << group.back() << " (";
    for (size_t j = 0; j < group.size(); ++j) s << (j ? ", " : "") << eigen.values[group[j]];
    s << ")";
  }
  return s.str();
}

}  // namespace cshapes
