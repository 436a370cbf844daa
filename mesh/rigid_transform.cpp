#include "cshapes/mesh/rigid_transform.h"

#include <Eigen/SVD>
#include <algorithm>
#include <cmath>
#include <random>
#include <vector>

#include "cshapes/support/error.h"

namespace cshapes {

Points RigidTransform::apply(const Points& X) const {
  Points Y = X * rotation.transpose();
  Y.rowwise() += translation.transpose();
  return Y;
}

RigidTransform RigidTransform::inverse() const {
  RigidTransform inv;
  inv.rotation = rotation.transpose();
  inv.translation = -(inv.rotation * translation);
  return inv;
}

Eigen::Matrix4d RigidTransform::matrix() const {
  Eigen::Matrix4d M = Eigen::Matrix4d::Identity();
  M.topLeftCorner<3, 3>() = rotation;
  M.topRightCorner<3, 1>() = translation;
  return M;
}

RigidTransform operator*(const RigidTransform& a, const RigidTransform& b) {
  RigidTransform c;
  c.rotation = a.rotation * b.rotation;
  c.translation = a.rotation * b.translation + a.translation;
  return c;
}

RigidTransform random_rigid_transform(uint64_t seed, double translation_scale, bool reflection) {
  std::mt19937_64 rng(seed);
  std::normal_distribution<double> normal(0.0, 1.0);
  Eigen::Quaterniond q;
  do {
    q = Eigen::Quaterniond(normal(rng), normal(rng), normal(rng), normal(rng));
  } while (q.norm() < 1e-6);
  q.normalize();
  RigidTransform T;
  T.rotation = q.toRotationMatrix();
  if (reflection) T.rotation.col(2) *= -1;  // R·diag(1, 1, −1): mirror z first, then rotate
  for (int k = 0; k < 3; ++k) T.translation[k] = translation_scale * normal(rng);
  return T;
}

Eigen::Matrix3d closest_orthogonal_matrix(const Eigen::Matrix3d& H, int determinant) {
  CSHAPES_REQUIRE(determinant == 1 || determinant == -1,
                  "closest_orthogonal_matrix: determinant must be +1 or -1, got ", determinant);
  Eigen::JacobiSVD<Eigen::Matrix3d> svd(H, Eigen::ComputeFullU | Eigen::ComputeFullV);
  const Eigen::Matrix3d& U = svd.matrixU();
  const Eigen::Matrix3d& V = svd.matrixV();
  // R = V·D·Uᵀ with D = diag(1, 1, s), written as a full 3×3 product: the rounding of this expression is the
  // one the Coulomb iteration's forms were computed with (V·diag(d)·Uᵀ rounds differently in half the cases,
  // and the iteration amplifies a last-bit difference).
  Eigen::Matrix3d D = Eigen::Matrix3d::Identity();
  D(2, 2) = (V * U.transpose()).determinant() * determinant < 0 ? -1.0 : 1.0;
  return V * D * U.transpose();
}

namespace {

// Means of A and B and the cross-covariance of the centred rows, H(r, c) = Σ w (a_r − ā_r)(b_c − b̄_c),
// column by column (no n×3 temporaries); unit weights when w is empty.
struct CentredCovariance {
  Eigen::RowVector3d a_mean, b_mean;
  Eigen::Matrix3d H;
};

CentredCovariance centred_covariance(const Points& A, const Points& B, const Eigen::VectorXd& w) {
  CentredCovariance c;
  if (w.size() == 0) {
    c.a_mean = A.colwise().mean();
    c.b_mean = B.colwise().mean();
    for (int r = 0; r < 3; ++r)
      for (int k = 0; k < 3; ++k)
        c.H(r, k) = ((A.col(r).array() - c.a_mean(r)) * (B.col(k).array() - c.b_mean(k))).sum();
    return c;
  }
  const double total = w.sum();
  for (int r = 0; r < 3; ++r) {
    c.a_mean(r) = (A.col(r).array() * w.array()).sum() / total;
    c.b_mean(r) = (B.col(r).array() * w.array()).sum() / total;
  }
  for (int r = 0; r < 3; ++r)
    for (int k = 0; k < 3; ++k)
      c.H(r, k) = (w.array() * (A.col(r).array() - c.a_mean(r)) * (B.col(k).array() - c.b_mean(k))).sum();
  return c;
}

// Each row a of A ↦ R·(a − a_mean) + b_mean, written coordinate by coordinate.
void apply_centred(Points& A, const Eigen::Matrix3d& R, const Eigen::RowVector3d& a_mean,
                   const Eigen::RowVector3d& b_mean) {
  const Index n = A.rows();
  double* x = A.data();
  double* y = x + n;
  double* z = y + n;
  for (Index i = 0; i < n; ++i) {
    const double ax = x[i] - a_mean(0), ay = y[i] - a_mean(1), az = z[i] - a_mean(2);
    x[i] = R(0, 0) * ax + R(0, 1) * ay + R(0, 2) * az + b_mean(0);
    y[i] = R(1, 0) * ax + R(1, 1) * ay + R(1, 2) * az + b_mean(1);
    z[i] = R(2, 0) * ax + R(2, 1) * ay + R(2, 2) * az + b_mean(2);
  }
}

// RMS of the rows of A moved by (R, a_mean, b_mean) against B, weighted by w (unit weights when empty).
double rms_after(const Points& A, const Points& B, const Eigen::VectorXd& w, const Eigen::Matrix3d& R,
                 const Eigen::RowVector3d& a_mean, const Eigen::RowVector3d& b_mean) {
  Points moved = A;
  apply_centred(moved, R, a_mean, b_mean);
  // Unit weights: the expression the Coulomb iteration's shape-change test has always used (same rounding).
  if (w.size() == 0) return std::sqrt((moved - B).rowwise().squaredNorm().mean());
  return std::sqrt((moved - B).rowwise().squaredNorm().dot(w) / w.sum());
}

// The rows of P, Q (and w) finite in both, gathered; `all` when every row is.
struct UsableRows {
  Points P, Q;
  Eigen::VectorXd w;
  bool all = true;
};

UsableRows finite_rows(const Points& P, const Points& Q, const Eigen::VectorXd& w) {
  UsableRows u;
  std::vector<Index> rows;
  rows.reserve(static_cast<size_t>(P.rows()));
  for (Index i = 0; i < P.rows(); ++i)
    if (P.row(i).allFinite() && Q.row(i).allFinite()) rows.push_back(i);
  if (static_cast<Index>(rows.size()) == P.rows()) return u;
  u.all = false;
  u.P.resize(static_cast<Index>(rows.size()), 3);
  u.Q.resize(static_cast<Index>(rows.size()), 3);
  if (w.size()) u.w.resize(static_cast<Index>(rows.size()));
  for (size_t k = 0; k < rows.size(); ++k) {
    const Index i = static_cast<Index>(k);
    u.P.row(i) = P.row(rows[k]);
    u.Q.row(i) = Q.row(rows[k]);
    if (w.size()) u.w[i] = w[rows[k]];
  }
  return u;
}

}  // namespace

RigidFitResult fit_rigid_transform(const Points& P_all, const Points& Q_all, const RigidFitOptions& options) {
  CSHAPES_REQUIRE(P_all.rows() == Q_all.rows(), "fit_rigid_transform: need equally many rows, got ",
                  P_all.rows(), " and ", Q_all.rows());
  CSHAPES_REQUIRE(options.determinant == 1 || options.determinant == -1 || options.determinant == 0,
                  "fit_rigid_transform: determinant must be +1, -1 or 0 (either), got ", options.determinant);
  CSHAPES_REQUIRE(options.weights.size() == 0 || options.weights.size() == P_all.rows(),
                  "fit_rigid_transform: ", options.weights.size(), " weights for ", P_all.rows(), " rows");
  CSHAPES_REQUIRE(options.weights.size() == 0 || options.weights.minCoeff() >= 0,
                  "fit_rigid_transform: weights must be non-negative");
  UsableRows usable;
  if (options.skip_nonfinite_rows) {
    usable = finite_rows(P_all, Q_all, options.weights);
  } else {
    CSHAPES_REQUIRE(
        P_all.allFinite() && Q_all.allFinite(),
        "fit_rigid_transform: non-finite coordinates (set skip_nonfinite_rows to ignore those rows)");
  }
  const Points& P = usable.all ? P_all : usable.P;
  const Points& Q = usable.all ? Q_all : usable.Q;
  const Eigen::VectorXd& w = usable.all ? options.weights : usable.w;
  CSHAPES_REQUIRE(P.rows() > 0, "fit_rigid_transform: no usable rows (of ", P_all.rows(), ")");
  CSHAPES_REQUIRE(w.size() == 0 || w.sum() > 0, "fit_rigid_transform: the weights sum to zero");

  const CentredCovariance c = centred_covariance(P, Q, w);
  RigidFitResult result;
  result.rows_used = P.rows();
  bool have_one = false;
  for (int determinant : {+1, -1}) {  // with determinant 0 both, a rotation winning a tie
    if (options.determinant != 0 && options.determinant != determinant) continue;
    const Eigen::Matrix3d R = closest_orthogonal_matrix(c.H, determinant);
    const double rms = rms_after(P, Q, w, R, c.a_mean, c.b_mean);
    if (!have_one || rms < result.rms) {
      have_one = true;
      result.rms = rms;
      result.transform.rotation = R;
      result.transform.translation = c.b_mean.transpose() - R * c.a_mean.transpose();
    }
  }
  return result;
}

RigidTransform best_rigid_transform(const Points& P, const Points& Q, int determinant,
                                    const Eigen::VectorXd& weights) {
  RigidFitOptions options;
  options.determinant = determinant;
  options.weights = weights;
  return fit_rigid_transform(P, Q, options).transform;
}

void rigid_align_in_place(Points& A, const Points& B, int determinant) {
  CSHAPES_REQUIRE(A.rows() == B.rows(), "rigid_align: ", A.rows(), " vs ", B.rows(), " points");
  if (A.rows() == 0) return;
  const CentredCovariance c = centred_covariance(A, B, {});
  apply_centred(A, closest_orthogonal_matrix(c.H, determinant), c.a_mean, c.b_mean);
}

Points rigid_align(const Points& A, const Points& B) {
  Points moved = A;
  rigid_align_in_place(moved, B);
  return moved;
}

double aligned_rms(const Points& A, const Points& B, bool allow_reflection) {
  CSHAPES_REQUIRE(A.rows() == B.rows(), "aligned_rms: ", A.rows(), " vs ", B.rows(), " points");
  bool any_usable = false;
  for (Index i = 0; i < A.rows() && !any_usable; ++i)
    any_usable = A.row(i).allFinite() && B.row(i).allFinite();
  if (!any_usable) return 0;
  RigidFitOptions options;
  options.determinant = allow_reflection ? 0 : +1;
  options.skip_nonfinite_rows = true;
  return fit_rigid_transform(A, B, options).rms;
}

double rigid_rms_distance(const Points& A, const Points& B) {
  return aligned_rms(A, B, false);
}

}  // namespace cshapes
