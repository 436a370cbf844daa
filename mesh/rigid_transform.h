// Rigid motions x ↦ R·x + t (R orthogonal: a rotation, or a reflection when det R = −1) and the closed-form
// least-squares rigid motion between two point sets with corresponding rows (Kabsch 1976, Umeyama 1991).
// One implementation for its three users: the ICP step (matching/icp.cpp), the removal of rigid motion in
// the Coulomb iteration (canon/coulomb.cpp) and the vertex-wise RMS between two forms of the same mesh.
//
// The fit, for rows P_i, Q_i paired and weights w_i ≥ 0:
//   minimise Σ_i w_i ‖R·P_i + t − Q_i‖²  over orthogonal R with the requested determinant, and t.
//   p̄, q̄ the weighted means; H = Σ_i w_i (P_i − p̄)(Q_i − q̄)ᵀ = U·Σ·Vᵀ (SVD);
//   R = V·diag(1, 1, s)·Uᵀ with s = ±1 chosen so that det R is the one asked for; t = q̄ − R·p̄.
// Means are taken first and the cross-covariance of the centred rows second (two passes), which keeps H
// accurate for point sets far from the origin. Cost O(m) for m pairs, plus one 3×3 SVD.
// Degenerate sets (all points on a line or coincident) give one of the minimisers.
#pragma once

#include <cstdint>

#include "cshapes/support/types.h"

namespace cshapes {

// x ↦ rotation·x + translation. `rotation` is orthogonal; its determinant is -1 for a reflection.
struct RigidTransform {
  Eigen::Matrix3d rotation = Eigen::Matrix3d::Identity();
  Eigen::Vector3d translation = Eigen::Vector3d::Zero();

  bool is_reflection() const { return rotation.determinant() < 0; }
  Eigen::Vector3d apply(const Eigen::Vector3d& x) const { return rotation * x + translation; }
  // Every row of X (n×3) transformed.
  Points apply(const Points& X) const;
  RigidTransform inverse() const;
  // The 4×4 homogeneous matrix [R t; 0 1].
  Eigen::Matrix4d matrix() const;
};
// Composition: (a * b).apply(x) == a.apply(b.apply(x)).
RigidTransform operator*(const RigidTransform& a, const RigidTransform& b);

// A rotation uniformly distributed on SO(3) (a normalised Gaussian quaternion), composed with the mirror
// z ↦ −z when `reflection`, and a translation with independent N(0, translation_scale²) coordinates.
// Deterministic for a given seed. For tests and benchmarks.
RigidTransform random_rigid_transform(uint64_t seed, double translation_scale = 1.0, bool reflection = false);

// The orthogonal matrix R maximising trace(R·H) (equivalently: the rotation part of the fit above for the
// cross-covariance H = Σ w (p − p̄)(q − q̄)ᵀ), with det R = determinant (+1 or −1). Flipping the axis of
// the smallest singular value costs least (Umeyama 1991, Lemma). For callers that accumulate H themselves
// (ICP visits its pairs through index lists without gathering them).
Eigen::Matrix3d closest_orthogonal_matrix(const Eigen::Matrix3d& H, int determinant);

struct RigidFitOptions {
  // +1: rotations only; −1: reflections only; 0: whichever of the two leaves the smaller residual (a
  // rotation on a tie).
  int determinant = +1;
  Eigen::VectorXd weights;  // w_i ≥ 0, one per row; empty: all 1
  // true: rows with a non-finite coordinate in P or in Q take no part (a canonical form's dropped vertices
  // are NaN rows); false: such rows are an error.
  bool skip_nonfinite_rows = false;
};

struct RigidFitResult {
  RigidTransform transform;  // maps P onto Q: Q_i ≈ R·P_i + t
  // sqrt(Σ w_i ‖R·P_i + t − Q_i‖² / Σ w_i) over the rows used, in the units of Q.
  double rms = 0;
  Index rows_used = 0;  // rows that took part (all, unless non-finite rows were skipped)
};

// The least-squares rigid motion of P onto Q (both m×3, rows paired; at least one usable row with a
// positive weight). Throws cshapes::Error on mismatched sizes, a bad determinant, negative or
// all-zero weights, or non-finite rows when they are not skipped.
RigidFitResult fit_rigid_transform(const Points& P, const Points& Q, const RigidFitOptions& options = {});

// Shorthand: fit_rigid_transform(P, Q, {determinant, weights}).transform (determinant +1, −1 or 0).
RigidTransform best_rigid_transform(const Points& P, const Points& Q, int determinant = +1,
                                    const Eigen::VectorXd& weights = {});

// Moves A (n×3) rigidly onto B (same n, rows paired, all finite), unit weights: each row a ↦ R·(a − ā) + b̄
// with the best R of the requested determinant (+1 or −1). Written into A without n×3 temporaries (the
// Coulomb iteration calls it every step). n = 0 leaves A empty.
void rigid_align_in_place(Points& A, const Points& B, int determinant = +1);
// The same on a copy: A moved onto B. Reflections excluded.
Points rigid_align(const Points& A, const Points& B);

// The vertex-wise RMS distance after the best rigid alignment of A onto B (same vertex order, unit weights):
// sqrt(mean_i ‖R·(a_i − ā) + b̄ − b_i‖²), over the rows finite in both A and B (vertices a repair dropped are
// NaN rows), minimised over rotations, and over reflections too when allow_reflection. Units of B. 0 when
// no row is usable. Symmetric in A and B only up to rounding.
double aligned_rms(const Points& A, const Points& B, bool allow_reflection);

// aligned_rms(A, B, false): the RMS after aligning by a rotation only.
double rigid_rms_distance(const Points& A, const Points& B);

}  // namespace cshapes
