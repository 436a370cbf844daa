// Laplace–Beltrami eigenpairs of a mesh or a point cloud: the k smallest solutions of the generalized problem
//
//   L φ = λ M φ,   φᵀ M φ = 1,   0 = λ_0 ≤ λ_1 ≤ ... ≤ λ_{k-1},
//
// reusable by every spectral method (canon/spectral_embedding.h: the eigenmap/GPS and diffusion-map
// canonical forms). Eigenvalues in 1/length² (the mesh's units), eigenvectors M-orthonormal (in 1/length).
//
// Operators
//   * Triangle meshes: L the cotangent stiffness matrix (L·1 = 0, positive semi-definite), M the lumped
//     (barycentric: a third of each incident triangle) mass, both on the intrinsic Delaunay triangulation
//     (operators/intrinsic_delaunay.h; the default) or on the mesh's own triangles. Both work on mollified edge
//     lengths, so degenerate triangles are harmless. Why intrinsic Delaunay by default: its weights are
//     non-negative, and on meshes with obtuse or needle triangles its eigenvalues are markedly closer to the
//     analytic ones (docs/design.md, "Spectral canonical forms": measured on a UV sphere and a skewed
//     rectangle), while on well-shaped meshes the two agree (few or no flips).
//   * Point clouds (no faces): the graph Laplacian of the symmetric kNN graph (mesh/knn_graph.h) with
//     Gaussian weights w_ij = exp(-|x_i - x_j|²/ε), ε the mean squared kNN edge length, density-normalised
//     as Coifman & Lafon's α = 1 (w̃_ij = w_ij/(q_i q_j), q_i = 1 + Σ_j w_ij), L = D̃ − W̃, M = D̃ scaled by
//     ε/4: for a Gaussian kernel (I − P)·4/ε tends to −Δ as ε → 0, so the eigenvalues are in 1/length² as a
//     mesh's. With a kNN-truncated kernel they approximate the Laplace–Beltrami eigenvalues only roughly
//     (about 10-20% on a sampled sphere; their ratios better); the forms built on them are scale-consistent.
//
// Solver: shift-invert Lanczos (Spectra's SymEigsShiftSolver) on the symmetric form M^{-1/2} L M^{-1/2},
// whose shifted inverse M^{1/2} (L − σM)^{-1} M^{1/2} needs one sparse Cholesky factorisation of L − σM
// (operators/sparse_cholesky.h: CHOLMOD) and two triangular solves per product. σ is slightly negative
// (−kShiftFactor × the operator's mean diagonal L_ii/M_ii divided by n, about 10⁻³/area: at most a few
// tenths of a percent of λ_1 on any reasonable shape) so L − σM is positive definite even though L is
// singular, and the smallest eigenvalues are the ones nearest σ. Meshes of at most kDenseEigenVertices
// vertices (or with k close to n) are solved densely (Eigen's generalized self-adjoint solver).
// Signs: each eigenvector is made positive at its largest-magnitude entry: deterministic for one input, but
// no canonical choice (on a symmetric shape two entries tie); a sign flip of an eigenvector is a reflection
// of the form, which ICP's starts cover (matching/icp.h).
// Several components: L has one zero eigenvalue per component (reported as a near-multiple group at 0); the
// canonical-form methods keep the largest component (their mesh requirements), as cmds does.
// Cost: the factorisation (~O(n^1.5) on meshes) and ~2-4 k operator products of O(nnz(factor)) each.
#pragma once

#include <Eigen/SparseCore>
#include <string>
#include <vector>

#include "cshapes/mesh/knn_graph.h"
#include "cshapes/mesh/mesh.h"
#include "cshapes/support/option_fields.h"
#include "cshapes/support/option_limits.h"
#include "cshapes/support/progress.h"

namespace cshapes {

namespace laplace_beltrami_limits {
inline constexpr Limit kEigenpairs = integer_limit("eigenpairs", 5, 500);
inline constexpr Limit kNearMultipleGap = number_limit("near-multiple-gap", 0, 1);
}  // namespace laplace_beltrami_limits

// σ = −kShiftFactor · mean(L_ii / M_ii) / n (see above).
inline constexpr double kShiftFactor = 1e-3;
// At most this many vertices: dense generalized eigensolver (exact, O(n³), 0.1 s at 400).
inline constexpr Index kDenseEigenVertices = 300;

struct LaplaceBeltramiOptions {
  // k: eigenpairs computed, the constant one (λ_0 = 0) included. The forms use λ_1..λ_3; the rest tell
  // whether λ_3 is near-multiple with λ_4 (the form's third axis then undetermined) and how much of the
  // diffusion distance the form keeps. 10: one Lanczos run of ncv = 21 vectors.
  int eigenpairs = 10;
  // Cotangent Laplacian on the intrinsic Delaunay triangulation (true) or on the mesh's triangles (false).
  bool intrinsic_delaunay = true;
  // Consecutive eigenvalues with (λ_{i+1} − λ_i) ≤ gap · λ_{i+1} are reported as near-multiple. 0.02: the
  // eigenvalue error of a 5,000-vertex mesh is ~0.1-1% (tests/spectral_test.cpp), so closer pairs may be
  // exact multiples split by discretisation, whose eigenvectors mix freely.
  double near_multiple_gap = 0.02;
  // Polled (support/progress.h) before each Lanczos product, one sparse triangular solve pair, and around
  // the factorisation before them (operators/sparse_cholesky.h: before its ordering, before and after its
  // numeric step): where a stop (Ctrl-C in Python) is heard. Neither step of the factorisation is
  // interrupted inside.
  ProgressFn progress;

  // Every field by name, for cache keys (support/option_fields.h).
  template <class Self, class Visit>
  static void for_each_field(Self& o, Visit&& visit) {
    visit("eigenpairs", o.eigenpairs);
    visit("intrinsic_delaunay", o.intrinsic_delaunay);
    // Changes only the report (near_multiple, the warning), but that is part of the cached summary.
    visit("near_multiple_gap", o.near_multiple_gap);
    visit("progress", o.progress, kNoEffect);  // hears a stop, computes nothing
  }
};

// The matrices of the generalized problem.
struct LaplacianMatrices {
  Eigen::SparseMatrix<double> L;  // n×n symmetric, positive semi-definite, L·1 = 0
  Eigen::VectorXd mass;           // n, positive for every vertex in a face (a point with an edge)
  std::string kind;               // "intrinsic-delaunay", "cotangent" or "knn-graph"
  Index flips = 0;                // intrinsic Delaunay: edges flipped
  double mollification = 0;       // the length added to every edge (operators/intrinsic_delaunay.h)
};

// Cotangent stiffness and barycentric mass of a triangle mesh (on its intrinsic Delaunay triangulation when
// intrinsic_delaunay). Throws on a mesh without faces. Vertices in no face get mass 0 and an empty row.
// `poll` (support/progress.h) is polled between the triangulation and the operator.
LaplacianMatrices cotangent_laplacian(const Mesh& mesh, bool intrinsic_delaunay = true, const ProgressFn& poll = {});
// The kNN graph Laplacian of a point cloud (see above). Throws for fewer than 2 points.
LaplacianMatrices knn_graph_laplacian(const Points& P, const KnnGraphOptions& knn = {});
// The mesh's operator: cotangent_laplacian for triangle meshes, knn_graph_laplacian for point clouds.
LaplacianMatrices laplace_beltrami_matrices(const Mesh& mesh, const LaplaceBeltramiOptions& options = {},
                                            const KnnGraphOptions& knn = {});

struct LaplaceBeltramiEigen {
  Eigen::VectorXd values;   // k eigenvalues, increasing
  Eigen::MatrixXd vectors;  // n×k, column i the eigenvector of values[i], M-orthonormal
  Eigen::VectorXd mass;     // n: M's diagonal
  double area = 0;          // Σ mass (the surface area of a mesh)
  std::string laplacian;    // LaplacianMatrices::kind
  std::string solver;       // "shift-invert lanczos (cholmod)" or "dense"
  Index operator_products = 0;  // shift-invert: products with the inverse (each two triangular solves)
  Index flips = 0;              // intrinsic Delaunay flips
  // Groups of consecutive indices whose eigenvalues are near-multiple (options.near_multiple_gap), each of
  // at least two indices, in increasing order; several components give a group at λ = 0.
  std::vector<std::vector<int>> near_multiple;
  double seconds = 0;
};

// The k = options.eigenpairs smallest eigenpairs of the generalized problem (dense for small n, otherwise
// shift-invert Lanczos; see above). Throws cshapes::Error (naming `what`) when the factorisation fails or
// Lanczos does not converge, and for k ≥ n.
LaplaceBeltramiEigen laplace_beltrami_eigen(const LaplacianMatrices& A, const LaplaceBeltramiOptions& options,
                                            const std::string& what = "Laplace-Beltrami eigenpairs");
LaplaceBeltramiEigen laplace_beltrami_eigen(const Mesh& mesh, const LaplaceBeltramiOptions& options = {},
                                            const KnnGraphOptions& knn = {});
// All n eigenpairs by the dense solver (the reference the tests compare the sparse solver against).
LaplaceBeltramiEigen laplace_beltrami_eigen_dense(const LaplacianMatrices& A,
                                                  const LaplaceBeltramiOptions& options = {});

// Near-multiple groups of increasing `values` (see LaplaceBeltramiEigen::near_multiple).
std::vector<std::vector<int>> near_multiple_groups(const Eigen::VectorXd& values, double gap);
// One line describing them: "near-multiple eigenvalues: λ1..λ3 (2.001, 2.003, 2.004)"; "" when none.
std::string near_multiple_description(const LaplaceBeltramiEigen& eigen);

}  // namespace cshapes
