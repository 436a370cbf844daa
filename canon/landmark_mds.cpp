#include "canon/landmark_mds.h"

#include <Eigen/Eigenvalues>

#include <cmath>
#include <limits>

#include "core/error.h"
#include "core/serial_eigen_products.h"
#include "core/timing.h"

namespace cshapes {

namespace {

// Columns of points processed together: a block's squared distances (L × block doubles) stay small.
constexpr Index kPointBlock = 1024;

void check_rows(const Eigen::MatrixXf& rows, const std::vector<int>& landmarks) {
  const Index L = rows.rows(), n = rows.cols();
  CSHAPES_REQUIRE(static_cast<Index>(landmarks.size()) == L, "landmark MDS: ", landmarks.size(),
                  " landmarks for ", L, " rows");
  CSHAPES_REQUIRE(L >= 4, "landmark MDS: needs at least 4 landmarks for a 3-D embedding, got ", L);
  std::vector<char> seen(n, 0);
  for (int l : landmarks) {
    CSHAPES_REQUIRE(l >= 0 && l < n, "landmark MDS: landmark vertex ", l, " out of range 0..", n - 1);
    CSHAPES_REQUIRE(!seen[l], "landmark MDS: landmark vertex ", l, " given twice");
    seen[l] = 1;
  }
  for (Index j = 0; j < n; ++j)
    for (Index k = 0; k < L; ++k)
      if (!(rows(k, j) >= 0 && std::isfinite(rows(k, j))))
        fail("landmark MDS: the distance from landmark ", landmarks[k], " (row ", k, ") to point ", j, " is ",
             rows(k, j), "; distances must be finite and non-negative");
}

// The landmarks' distances among themselves, symmetrised ((D + Dᵀ)/2, zero diagonal), L × L.
Eigen::MatrixXd landmark_block(const Eigen::MatrixXf& rows, const std::vector<int>& landmarks) {
  const Index L = rows.rows();
  Eigen::MatrixXd block(L, L);
  for (Index j = 0; j < L; ++j)
    for (Index i = 0; i < L; ++i) block(i, j) = rows(i, landmarks[j]);
  block = 0.5 * (block + block.transpose()).eval();
  block.diagonal().setZero();
  return block;
}

// The classical MDS of the landmarks and the triangulation map: Y (L×3) and L^# (3×L), δ_μ.
struct LandmarkFrame {
  Points Y;
  Eigen::Matrix<double, 3, Eigen::Dynamic> pseudo_inverse;  // rows v_iᵀ/√λ_i, zero where λ_i ≤ 0
  Eigen::VectorXd mean_squared;                             // δ_μ
  Eigen::Vector3d eigenvalues;
  double explained_energy = 0;
};

LandmarkFrame landmark_frame(const Eigen::MatrixXd& block) {
  const Index L = block.rows();
  const Eigen::MatrixXd squared = block.cwiseAbs2();
  LandmarkFrame f;
  f.mean_squared = squared.rowwise().mean();
  // B = −½ J Δ J, centring rows and columns (Δ symmetric).
  Eigen::MatrixXd B = squared;
  B.rowwise() -= B.colwise().mean();
  B.colwise() -= B.rowwise().mean();
  B *= -0.5;
  Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eig(B);
  CSHAPES_REQUIRE(eig.info() == Eigen::Success, "landmark MDS: the eigensolver failed on the ", L, "×", L,
                  " landmark block");
  f.Y = Points::Zero(L, 3);
  f.pseudo_inverse.setZero(3, L);
  double top_energy = 0;
  for (int axis = 0; axis < 3; ++axis) {
    const double lambda = eig.eigenvalues()[L - 1 - axis];  // ascending order
    f.eigenvalues[axis] = lambda;
    top_energy += lambda * lambda;
    if (lambda <= 0) continue;
    const Eigen::VectorXd v = eig.eigenvectors().col(L - 1 - axis);
    f.Y.col(axis) = std::sqrt(lambda) * v;
    f.pseudo_inverse.row(axis) = v.transpose() / std::sqrt(lambda);
  }
  const double frobenius = eig.eigenvalues().squaredNorm();
  f.explained_energy = frobenius > 0 ? top_energy / frobenius : 0;
  return f;
}

}  // namespace

const std::vector<std::string>& mds_solver_names() {
  static const std::vector<std::string> names = {"full", "landmarks", "auto"};  // MdsSolver's order
  return names;
}

MdsSolver parse_mds_solver(const std::string& name) {
  const std::vector<std::string>& names = mds_solver_names();
  for (size_t k = 0; k < names.size(); ++k)
    if (names[k] == name) return static_cast<MdsSolver>(k);
  fail("mds solver: unknown '", name, "'; known: full, landmarks, auto");
}

std::string to_string(MdsSolver solver) {
  return mds_solver_names().at(static_cast<size_t>(solver));
}

bool mds_uses_landmarks(const MdsSolverOptions& options, Index n, double available_bytes) {
  switch (options.solver) {
    case MdsSolver::Full:
      return false;
    case MdsSolver::Landmarks:
      return true;
    case MdsSolver::Auto:
      break;
  }
  if (n > options.auto_full_max_vertices) return true;
  const double matrix_bytes = 4.0 * static_cast<double>(n) * static_cast<double>(n);
  return available_bytes >= 0 && matrix_bytes > 0.5 * available_bytes;
}

LandmarkMdsResult landmark_classical_mds(const Eigen::MatrixXf& rows, const std::vector<int>& landmarks) {
  const SerialEigenProducts serial_eigen_products;  // bit-identical for any thread count
  const auto start = WallClock::now();
  check_rows(rows, landmarks);
  const Index n = rows.cols();
  const LandmarkFrame frame = landmark_frame(landmark_block(rows, landmarks));
  LandmarkMdsResult result;
  result.eigenvalues = frame.eigenvalues;
  result.explained_energy = frame.explained_energy;
  result.X.resize(n, 3);
  // x_a = −½ L^# (δ_a − δ_μ), in blocks of points.
#pragma omp parallel for schedule(static)
  for (Index j0 = 0; j0 < n; j0 += kPointBlock) {
    const Index count = std::min(kPointBlock, n - j0);
    Eigen::MatrixXd delta = rows.middleCols(j0, count).cast<double>().cwiseAbs2();
    delta.colwise() -= frame.mean_squared;
    result.X.middleRows(j0, count) = (-0.5 * frame.pseudo_inverse * delta).transpose();
  }
  result.X.rowwise() -= result.X.colwise().mean();
  result.seconds = seconds_since(start);
  return result;
}

LandmarkMdsResult landmark_smacof(const Eigen::MatrixXf& rows, const std::vector<int>& landmarks,
                                  const SmacofOptions& smacof_options, int interpolation_iterations,
                                  const Points& start_configuration) {
  const SerialEigenProducts serial_eigen_products;  // bit-identical for any thread count
  const auto start = WallClock::now();
  check_rows(rows, landmarks);
  CSHAPES_REQUIRE(interpolation_iterations >= 0,
                  "landmark SMACOF: interpolation iterations must be ≥ 0, not ", interpolation_iterations);
  const Index L = rows.rows(), n = rows.cols();
  const Eigen::MatrixXd block = landmark_block(rows, landmarks);
  const LandmarkFrame frame = landmark_frame(block);

  // Landmark weights: uniform, or the per-point weights summed over each landmark's Voronoi cell.
  SmacofOptions so = smacof_options;
  Eigen::VectorXd w = Eigen::VectorXd::Ones(L);
  if (smacof_options.vertex_weights.size() > 0) {
    CSHAPES_REQUIRE(smacof_options.vertex_weights.size() == n,
                    "landmark SMACOF: ", smacof_options.vertex_weights.size(), " vertex weights for ", n,
                    " points");
    w.setZero();
    for (Index j = 0; j < n; ++j) {
      Index nearest = 0;
      rows.col(j).minCoeff(&nearest);
      w[nearest] += smacof_options.vertex_weights[j];
    }
    w /= w.mean();
    so.vertex_weights = w;
  }
  LandmarkMdsResult result;
  result.eigenvalues = frame.eigenvalues;
  result.explained_energy = frame.explained_energy;
  CSHAPES_REQUIRE(start_configuration.rows() == 0 || start_configuration.rows() == L,
                  "landmark SMACOF: a start of ", start_configuration.rows(), " points for ", L,
                  " landmarks");
  result.landmark_smacof =
      smacof(block.cast<float>(), start_configuration.rows() ? start_configuration : frame.Y, so);
  result.landmark_normalized_stress = result.landmark_smacof.normalized_stress;
  const Points& Y = result.landmark_smacof.X;

  // Least-squares triangulation in SMACOF's frame: x = P (c − δ²), P = (AᵀA)⁻¹Aᵀ, A = 2(Y − ȳ).
  const Eigen::RowVector3d y_mean = Y.colwise().mean();
  const Eigen::MatrixXd A = 2.0 * (Y.rowwise() - y_mean);
  const Eigen::Matrix3d AtA = A.transpose() * A;
  const Eigen::MatrixXd P = AtA.completeOrthogonalDecomposition().pseudoInverse() * A.transpose();
  Eigen::VectorXd c = Y.rowwise().squaredNorm();
  c.array() -= c.mean();

  const double w_sum = w.sum();
  std::vector<char> is_landmark(n, 0);
  for (int l : landmarks) is_landmark[l] = 1;
  result.X.resize(n, 3);
  double stress_before = 0, stress_after = 0;
#pragma omp parallel for schedule(dynamic, 256) reduction(+ : stress_before, stress_after)
  for (Index j = 0; j < n; ++j) {
    if (is_landmark[j]) continue;
    const Eigen::VectorXd delta = rows.col(j).cast<double>();
    // Start beside the nearest landmark, at its distance, towards the linear triangulation: the point then
    // descends into the basin of its own neighbourhood (from the triangulation alone, points near folds
    // fell into the basin across the fold).
    Index nearest = 0;
    delta.minCoeff(&nearest);
    const Eigen::Vector3d y_near = Y.row(nearest).transpose();
    const Eigen::Vector3d towards = P * (c - delta.cwiseAbs2()) - y_near;
    Eigen::Vector3d x = y_near + (towards.norm() > 0 ? Eigen::Vector3d(delta[nearest] * towards.normalized())
                                                     : Eigen::Vector3d::Zero());
    const double energy = delta.cwiseAbs2().dot(w);
    auto point_stress = [&](const Eigen::Vector3d& p) {
      const Eigen::VectorXd d = (Y.rowwise() - p.transpose()).rowwise().norm();
      return energy > 0 ? (delta - d).cwiseAbs2().dot(w) / energy : 0.0;
    };
    stress_before += point_stress(x);
    // Guttman transforms of this point's stress with the landmarks fixed.
    for (int it = 0; it < interpolation_iterations; ++it) {
      Eigen::Vector3d next = Eigen::Vector3d::Zero();
      for (Index k = 0; k < L; ++k) {
        const Eigen::Vector3d y = Y.row(k).transpose();
        const double d = (x - y).norm();
        next += w[k] * (d > 0 ? y + (delta[k] / d) * (x - y) : y);
      }
      next /= w_sum;
      const bool settled = (next - x).norm() <= 1e-9 * (std::abs(delta.maxCoeff()) + 1e-300);
      x = next;
      if (settled) break;
    }
    stress_after += point_stress(x);
    result.X.row(j) = x.transpose();
  }
  for (Index k = 0; k < L; ++k) result.X.row(landmarks[k]) = Y.row(k);
  const double others = static_cast<double>(std::max<Index>(1, n - L));
  result.start_point_stress = stress_before / others;
  result.interpolated_point_stress = stress_after / others;
  result.X.rowwise() -= result.X.colwise().mean();
  result.seconds = seconds_since(start);
  return result;
}

}  // namespace cshapes
