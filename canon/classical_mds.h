// Classical scaling (Young & Householder 1938; Torgerson): the MDS canonical form of Elad & Kimmel by the
// eigendecomposition of the double-centred squared-distance matrix.
//
//   B = −½ J D∘D J,   J = I − 11ᵀ/n            (D∘D: entrywise squares)
//   X = [v₁ v₂ v₃] diag(√λ₁, √λ₂, √λ₃)       (λ₁ ≥ λ₂ ≥ λ₃ the largest eigenvalues of B, v their unit
//   vectors)
//
// For distances between points of R³, B = X Xᵀ of the centred points and the embedding is exact up to a rigid
// motion. Geodesic distances are not Euclidean: B then has negative eigenvalues, and how much of its spectrum
// is negative measures how far the metric is from any Euclidean one (see ClassicalMdsResult).
//
// Cost: neither B nor J is ever formed. Each product B·v is one streaming pass over the upper triangle of D
// (squares computed on the fly in double, each entry credited to its row and its column; centring applied
// to v before and to the result after), O(n²) time and O(n · threads) extra memory, OpenMP over 256×256
// tiles. The eigenpairs come from Spectra's implicitly restarted Lanczos method: about 30 products for the
// top three and the two most negative eigenvalues together (n = 3,505 to 22,738), plus one validating pass.
// Below dense_below points (200) B is formed and decomposed densely instead (Eigen's SelfAdjointEigenSolver,
// O(n³), under 10 ms at n = 200): Lanczos needs n > its subspace size (a tetrahedron, n = 4, cannot have
// one), and at that size the dense solver is cheaper anyway. Both paths give the same eigenpairs. D must be
// symmetric (entries below the diagonal are not read by the products). Entries must be finite and ≥ 0: an
// infinite entry (a disconnected mesh) is refused with the pair's indices.
#pragma once

#include "cshapes/support/distance_matrix.h"
#include "cshapes/support/option_fields.h"
#include "cshapes/support/progress.h"
#include "cshapes/support/types.h"

namespace cshapes {

struct ClassicalMdsOptions {
  int lanczos_vectors =
      20;  // Krylov subspace size (Spectra's ncv); more: fewer restarts, more memory (n each)
  double tolerance = 1e-10;  // accuracy of the eigenvalues relative to ‖B‖_F (Lanczos stopping test)
  int max_restarts = 1000;   // implicit restarts before giving up (throws)
  // Also compute the most negative eigenvalue of B (in the same Lanczos run: 2 more wanted eigenvalues).
  bool most_negative_eigenvalue = true;
  Index dense_below = 200;  // fewer points: dense eigendecomposition of B (no products, no Lanczos)
  ProgressFn progress;      // stage "classical mds": called after each product B·v (total unknown: 0)

  // Every field by name, for cache keys (support/option_fields.h). Self: ClassicalMdsOptions, const or not.
  template <class Self, class Visit>
  static void for_each_field(Self& o, Visit&& visit) {
    visit("lanczos_vectors", o.lanczos_vectors);
    visit("tolerance", o.tolerance);
    visit("max_restarts", o.max_restarts);
    // Two more wanted eigenvalues: another Lanczos run, so other last bits of X.
    visit("most_negative_eigenvalue", o.most_negative_eigenvalue);
    visit("dense_below", o.dense_below);       // the dense and the Lanczos path differ in the last bits
    visit("progress", o.progress, kNoEffect);  // reports, computes nothing
  }
};

struct ClassicalMdsResult {
  Points X;                     // n×3 canonical form, centred at the origin, in the units of D
  Eigen::Vector3d eigenvalues;  // λ₁ ≥ λ₂ ≥ λ₃, the eigenvalues of B used; a negative one gives a zero axis
  // Most negative eigenvalue λ_min of B (NaN when not computed). Zero or positive: B is semi-definite (the
  // distances are Euclidean in some dimension).
  double most_negative_eigenvalue = 0;  // (not computed by Lanczos for n < 8)
  // Spectrum summaries, exact, from one pass over D (traces of B and B²):
  double trace = 0;              // tr B = Σ λ = (1/2n) Σᵢⱼ Dᵢⱼ²
  double frobenius_squared = 0;  // ‖B‖²_F = Σ λ²
  // Fraction of the spectrum's energy the 3-D embedding keeps: (λ₁² + λ₂² + λ₃²) / ‖B‖²_F.
  double explained_energy = 0;
  // Bounds on the negative part of the spectrum, each relative to λ₁ + λ₂ + λ₃ (or to ‖B‖²_F for energy):
  //   negative_mass ≥ (λ₁ + λ₂ + λ₃ − tr B)      since Σ_{λ<0} |λ| = Σ_{λ>0} λ − tr B ≥ λ₁ + λ₂ + λ₃ − tr B
  //   negative_energy ≤ 1 − explained_energy    since Σ_{λ<0} λ² ≤ ‖B‖²_F − (λ₁² + λ₂² + λ₃²)
  double negative_mass_lower_bound = 0;    // max(0, λ₁+λ₂+λ₃ − tr B) / (λ₁+λ₂+λ₃)
  double negative_energy_upper_bound = 0;  // 1 − explained_energy
  int matrix_products = 0;                 // products B·v (each one pass over D); 0 on the dense path
  double seconds = 0;
};

// Classical MDS of a symmetric n×n distance matrix (n ≥ 4), single precision (the geodesic matrices).
ClassicalMdsResult classical_mds(const DistanceMatrix& D, const ClassicalMdsOptions& options = {});
// The same in double precision (tests against exact answers).
ClassicalMdsResult classical_mds(const Eigen::MatrixXd& D, const ClassicalMdsOptions& options = {});

}  // namespace cshapes
