#include "cshapes/mesh/rigid_transform.h"

#include <gtest/gtest.h>

#include <Eigen/SVD>
#include <algorithm>
#include <cmath>
#include <limits>
#include <random>

#include "cshapes/support/error.h"
#include "cshapes/data/synthetic.h"

namespace cshapes {
namespace rigid_transform_test {

double rms_radius(const Points& X) {
  return std::sqrt((X.rowwise() - X.colwise().mean()).rowwise().squaredNorm().mean());
}

// Relative error of a recovered transform: rotation in the Frobenius norm (dimensionless), translation
// relative to the shape's RMS radius; the larger of the two.
double transform_error(const RigidTransform& found, const RigidTransform& truth, double radius) {
  return std::max((found.rotation - truth.rotation).norm(),
                  (found.translation - truth.translation).norm() / radius);
}

Points mirror_z(const Points& X) {
  Points Y = X;
  Y.col(2) *= -1;
  return Y;
}

// The vertex-wise RMS as experiments/paper_experiment.cpp (vertexwise_rms) computed it before it moved to
// core: the finite rows gathered, the weighted Kabsch fit written with matrix products (means by a
// matrix-vector product, H by a matrix product), both determinants, the RMS of T.apply(A) − B. A second code
// path for aligned_rms.
double vertexwise_rms_reference(const Points& A_all, const Points& B_all) {
  std::vector<Index> rows;
  for (Index i = 0; i < A_all.rows(); ++i)
    if (A_all.row(i).allFinite() && B_all.row(i).allFinite()) rows.push_back(i);
  Points A(rows.size(), 3), B(rows.size(), 3);
  for (size_t k = 0; k < rows.size(); ++k) {
    A.row(k) = A_all.row(rows[k]);
    B.row(k) = B_all.row(rows[k]);
  }
  const Eigen::VectorXd w = Eigen::VectorXd::Ones(A.rows());
  const Eigen::Vector3d a_mean = (A.transpose() * w) / w.sum(), b_mean = (B.transpose() * w) / w.sum();
  const Eigen::Matrix3d H =
      (A.rowwise() - a_mean.transpose()).transpose() * w.asDiagonal() * (B.rowwise() - b_mean.transpose());
  Eigen::JacobiSVD<Eigen::Matrix3d> svd(H, Eigen::ComputeFullU | Eigen::ComputeFullV);
  double best = std::numeric_limits<double>::infinity();
  for (int det : {+1, -1}) {
    const double s = (svd.matrixV() * svd.matrixU().transpose()).determinant() * det < 0 ? -1.0 : 1.0;
    RigidTransform t;
    t.rotation = svd.matrixV() * Eigen::Vector3d(1, 1, s).asDiagonal() * svd.matrixU().transpose();
    t.translation = b_mean - t.rotation * a_mean;
    best = std::min(best, std::sqrt((t.apply(A) - B).rowwise().squaredNorm().mean()));
  }
  return best;
}

TEST(RigidTransform, ComposeInverseMatrix) {
  RigidTransform a = random_rigid_transform(1, 2.0, false), b = random_rigid_transform(2, 3.0, true);
  Eigen::Vector3d x(0.3, -1.2, 2.5);
  EXPECT_LT(((a * b).apply(x) - a.apply(b.apply(x))).norm(), 1e-12);
  EXPECT_LT((b.inverse().apply(b.apply(x)) - x).norm(), 1e-12);
  EXPECT_TRUE(b.is_reflection());
  EXPECT_FALSE(a.is_reflection());
  EXPECT_NEAR(std::abs(b.rotation.determinant()), 1.0, 1e-12);
  EXPECT_LT((b.rotation.transpose() * b.rotation - Eigen::Matrix3d::Identity()).norm(), 1e-12);
  Eigen::Vector4d h = b.matrix() * Eigen::Vector4d(x.x(), x.y(), x.z(), 1.0);
  EXPECT_LT((h.head<3>() - b.apply(x)).norm(), 1e-12);
}

TEST(BestRigidTransform, RecoversRotationsAndReflectionsExactly) {
  Points P = lumpy_blob(50, 3);
  for (int trial = 0; trial < 20; ++trial) {
    bool reflection = trial % 2;
    RigidTransform truth = random_rigid_transform(100 + trial, 5.0, reflection);
    Points Q = truth.apply(P);
    RigidTransform found = best_rigid_transform(P, Q, reflection ? -1 : 1);
    EXPECT_LT(transform_error(found, truth, rms_radius(P)), 1e-12) << "trial " << trial;
    // Asking for the other determinant gives a worse fit, never the truth.
    RigidTransform wrong = best_rigid_transform(P, Q, reflection ? 1 : -1);
    EXPECT_GT((wrong.apply(P) - Q).norm(), 1e-3 * (Q.norm()));
    // Either determinant: the right one is found.
    RigidFitOptions either;
    either.determinant = 0;
    const RigidFitResult fit = fit_rigid_transform(P, Q, either);
    EXPECT_EQ(fit.transform.is_reflection(), reflection) << "trial " << trial;
    EXPECT_LT(fit.rms, 1e-12 * rms_radius(Q));
    EXPECT_EQ(fit.rows_used, P.rows());
  }
}

// Scale robustness: the same problem at 1e-8 and 1e8 times the size, and far from the origin (the two-pass
// means keep the cross-covariance accurate there).
TEST(BestRigidTransform, ScaleAndOffsetInvariant) {
  const Points P0 = lumpy_blob(80, 21);
  const RigidTransform truth = random_rigid_transform(22, 1.0, true);
  for (double scale : {1e-8, 1.0, 1e8}) {
    for (double offset : {0.0, 1e5}) {
      const Points P = (P0.array() + offset).matrix() * scale;
      RigidTransform scaled_truth = truth;
      scaled_truth.translation *= scale;
      const Points Q = scaled_truth.apply(P);
      const RigidFitResult fit = fit_rigid_transform(P, Q, {-1, {}, false});
      // Relative to the coordinates' magnitude: far from the origin the data itself carry that much rounding.
      const double magnitude = scale * (1.0 + offset);
      EXPECT_LT((fit.transform.rotation - truth.rotation).norm(), 1e-9)
          << "scale " << scale << " offset " << offset;
      EXPECT_LT(fit.rms, 1e-12 * magnitude) << "scale " << scale << " offset " << offset;
    }
  }
}

TEST(BestRigidTransform, ZeroWeightsIgnorePairs) {
  Points P = lumpy_blob(40, 4);
  RigidTransform truth = random_rigid_transform(5, 1.0, false);
  Points Q = truth.apply(P);
  Eigen::VectorXd w = Eigen::VectorXd::Ones(40);
  for (int i = 0; i < 40; i += 4) {
    Q.row(i) += Eigen::RowVector3d(10, -7, 3);  // gross outliers...
    w[i] = 0;                                   // ...carrying no weight
  }
  EXPECT_LT(transform_error(best_rigid_transform(P, Q, 1, w), truth, rms_radius(P)), 1e-12);
  // Weights 2 count a row twice: the same as duplicating it.
  Points Pn = lumpy_blob(30, 6),
         Qn = random_rigid_transform(7, 1.0, false).apply(Pn) + 0.1 * lumpy_blob(30, 8);
  Eigen::VectorXd twice = Eigen::VectorXd::Ones(30);
  twice[3] = 2;
  Points Pd(31, 3), Qd(31, 3);
  Pd << Pn, Pn.row(3);
  Qd << Qn, Qn.row(3);
  RigidFitOptions weighted;
  weighted.weights = twice;
  const RigidFitResult a = fit_rigid_transform(Pn, Qn, weighted), b = fit_rigid_transform(Pd, Qd);
  EXPECT_LT(transform_error(a.transform, b.transform, rms_radius(Pn)), 1e-12);
  EXPECT_NEAR(a.rms, b.rms, 1e-12 * rms_radius(Qn));
}

TEST(BestRigidTransform, MinimisesAgainstPerturbations) {
  // The closed form is the least-squares optimum: any small rotation of it fits worse.
  Points P = lumpy_blob(60, 8);
  Points Q = random_rigid_transform(9, 1.0, false).apply(P) + 0.05 * lumpy_blob(60, 10);
  const RigidFitResult fit = fit_rigid_transform(P, Q);
  const RigidTransform& best = fit.transform;
  double cost = (best.apply(P) - Q).squaredNorm();
  EXPECT_NEAR(fit.rms, std::sqrt(cost / P.rows()), 1e-12 * rms_radius(Q));
  for (int k = 0; k < 10; ++k) {
    RigidTransform nudge = random_rigid_transform(200 + k, 1e-3, false);
    Eigen::AngleAxisd small(1e-3, nudge.rotation.col(0));
    RigidTransform other = best;
    other.rotation = small.toRotationMatrix() * best.rotation;
    other.translation += nudge.translation;
    EXPECT_GT((other.apply(P) - Q).squaredNorm(), cost);
  }
}

TEST(BestRigidTransform, SkipsNonFiniteRowsOnlyWhenAsked) {
  Points P = lumpy_blob(50, 12);
  const RigidTransform truth = random_rigid_transform(13, 2.0, true);
  Points Q = truth.apply(P);
  P(3, 1) = std::numeric_limits<double>::quiet_NaN();
  Q.row(17).setConstant(std::numeric_limits<double>::quiet_NaN());
  Q(30, 0) = std::numeric_limits<double>::infinity();
  RigidFitOptions o;
  o.determinant = 0;
  EXPECT_THROW(fit_rigid_transform(P, Q, o), Error);
  o.skip_nonfinite_rows = true;
  const RigidFitResult fit = fit_rigid_transform(P, Q, o);
  EXPECT_EQ(fit.rows_used, 47);
  EXPECT_LT(transform_error(fit.transform, truth, rms_radius(Q.topRows(3))), 1e-12);
  // Weights follow their rows when rows are skipped.
  o.weights = Eigen::VectorXd::Ones(50);
  o.weights[40] = 0;
  Q.row(40) += Eigen::RowVector3d(5, 5, 5);
  EXPECT_LT(transform_error(fit_rigid_transform(P, Q, o).transform, truth, rms_radius(Q.topRows(3))), 1e-12);
}

TEST(BestRigidTransform, RejectsBadInput) {
  Points P = lumpy_blob(10, 14);
  EXPECT_THROW(best_rigid_transform(P, P.topRows(5)), Error);
  EXPECT_THROW(best_rigid_transform(P, P, 2), Error);
  EXPECT_THROW(best_rigid_transform(P, P, 1, Eigen::VectorXd::Zero(10)), Error);
  Eigen::VectorXd negative = Eigen::VectorXd::Ones(10);
  negative[2] = -1;
  EXPECT_THROW(best_rigid_transform(P, P, 1, negative), Error);
  EXPECT_THROW(best_rigid_transform(Points(0, 3), Points(0, 3)), Error);
  EXPECT_THROW(closest_orthogonal_matrix(Eigen::Matrix3d::Identity(), 0), Error);
}

// Brute force: among many random orthogonal matrices of each determinant, none beats the closed form on
// trace(R·H), the quantity the fit maximises.
TEST(ClosestOrthogonalMatrix, MaximisesTraceAgainstRandomMatrices) {
  std::mt19937_64 rng(31);
  std::normal_distribution<double> normal(0, 1);
  for (int trial = 0; trial < 5; ++trial) {
    Eigen::Matrix3d H;
    for (int k = 0; k < 9; ++k) H(k / 3, k % 3) = normal(rng);
    for (int determinant : {+1, -1}) {
      const Eigen::Matrix3d R = closest_orthogonal_matrix(H, determinant);
      EXPECT_NEAR(R.determinant(), determinant, 1e-12);
      EXPECT_LT((R.transpose() * R - Eigen::Matrix3d::Identity()).norm(), 1e-12);
      const double best = (R * H).trace();
      for (int k = 0; k < 2000; ++k) {
        const RigidTransform other = random_rigid_transform(1000 * trial + k, 0.0, determinant < 0);
        EXPECT_LE((other.rotation * H).trace(), best + 1e-12 * H.norm());
      }
    }
  }
}

TEST(RigidAlign, MovesOntoTargetAndMatchesTheFit) {
  Points A = lumpy_blob(200, 15);
  Points B = random_rigid_transform(16, 3.0, false).apply(A) + 0.02 * lumpy_blob(200, 17);
  const RigidFitResult fit = fit_rigid_transform(A, B);
  const Points moved = rigid_align(A, B);
  EXPECT_LT((moved - fit.transform.apply(A)).cwiseAbs().maxCoeff(), 1e-12 * rms_radius(B));
  EXPECT_NEAR(std::sqrt((moved - B).rowwise().squaredNorm().mean()), fit.rms, 1e-12 * rms_radius(B));
  EXPECT_DOUBLE_EQ(rigid_rms_distance(A, B), aligned_rms(A, B, false));
  // Reflections excluded: a mirror image is not brought back.
  const Points M = mirror_z(A);
  EXPECT_GT(rigid_rms_distance(M, A), 1e-2 * rms_radius(A));
  Points reflected = M;
  rigid_align_in_place(reflected, A, -1);
  EXPECT_LT((reflected - A).cwiseAbs().maxCoeff(), 1e-12 * rms_radius(A));
  Points empty(0, 3);
  rigid_align_in_place(empty, Points(0, 3));
  EXPECT_EQ(empty.rows(), 0);
  EXPECT_THROW(rigid_align(A, B.topRows(3)), Error);
}

TEST(RigidAlign, RecoversARigidMotionOfAnIcosphere) {
  const Mesh m = icosphere(2);
  Points A = m.V;
  A.col(0) *= 2.0;  // not symmetric
  const Eigen::Matrix3d R = Eigen::AngleAxisd(0.7, Eigen::Vector3d(1, 2, 3).normalized()).toRotationMatrix();
  const Points B = (A * R.transpose()).rowwise() + Eigen::RowVector3d(3, -1, 2);
  EXPECT_LT((rigid_align(A, B) - B).cwiseAbs().maxCoeff(), 1e-12 * 10);
  EXPECT_LT(rigid_rms_distance(A, B), 1e-12 * 10);
  // A mirror image is not a rigid motion.
  Points M = A;
  M.col(1) *= -1;
  M.col(2) *= 1.3;
  EXPECT_GT(rigid_rms_distance(M, A), 1e-3);
}

TEST(AlignedRms, KnownAnswers) {
  const Points A = lumpy_blob(300, 18);
  const double r = rms_radius(A);
  const Points B = random_rigid_transform(19, 5.0, false).apply(A);
  EXPECT_LT(aligned_rms(A, B, false), 1e-12 * r);
  // A mirror image: zero only with reflections allowed.
  const Points M = random_rigid_transform(20, 5.0, true).apply(A);
  EXPECT_LT(aligned_rms(A, M, true), 1e-12 * r);
  EXPECT_GT(aligned_rms(A, M, false), 1e-2 * r);
  // A uniform shift of every vertex along a fixed direction is undone by the translation alone; a shift that
  // alternates in sign (+d, −d, ...) has zero mean and, against a centred symmetric-enough shape, cannot be
  // undone: its RMS is at most |d|.
  Points C = A;
  C.rowwise() += Eigen::RowVector3d(0.3, -0.2, 0.1);
  EXPECT_LT(aligned_rms(A, C, true), 1e-12 * r);
  Points D = A;
  const Eigen::RowVector3d d(0, 0, 1e-3 * r);
  for (Index i = 0; i < D.rows(); ++i) D.row(i) += (i % 2 ? -1.0 : 1.0) * d;
  EXPECT_LE(aligned_rms(A, D, true), d.norm() * (1 + 1e-9));
  EXPECT_GT(aligned_rms(A, D, true), 0.9 * d.norm());
  EXPECT_EQ(aligned_rms(Points(0, 3), Points(0, 3), true), 0.0);
  EXPECT_THROW(aligned_rms(A, A.topRows(4), true), Error);
}

// The numbers the paper experiment's vertex-wise RMS produced, NaN rows included, to rounding.
TEST(AlignedRms, ReproducesThePaperExperimentsVertexwiseRms) {
  for (int trial = 0; trial < 10; ++trial) {
    Points A = lumpy_blob(500, 40 + trial);
    Points B =
        random_rigid_transform(60 + trial, 3.0, trial % 2).apply(A) + 0.05 * lumpy_blob(500, 80 + trial);
    for (Index i = trial; i < 500; i += 37) (i % 2 ? A : B).row(i).setConstant(std::nan(""));
    const double reference = vertexwise_rms_reference(A, B);
    EXPECT_NEAR(aligned_rms(A, B, true), reference, 1e-13 * reference) << "trial " << trial;
  }
}

}  // namespace rigid_transform_test
}  // namespace cshapes
