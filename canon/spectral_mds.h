// Spectral MDS (Aflalo & Kimmel, "Spectral multidimensional scaling", PNAS 2013): classical MDS with the
// squared geodesic distance matrix restricted to the span of the first k Laplace–Beltrami eigenfunctions,
// fitted from the rows of L landmarks only (geodesics/landmark_geodesics.h), so neither the n × n matrix nor its
// all-pairs geodesics are ever formed.
//
//   D² ≈ Φ α Φᵀ,  α (k × k) = Φ_S⁺ D²_S M Φ   (least squares over the sampled rows S, M-weighted over the
//                                             columns: Φ is M-orthonormal, so the column fit is exact)
//   B = −½ J D² J with the area-weighted centring J: φ_0 (the constant) drops out, B ≈ Φ' (−½ α') Φ'ᵀ
//   X = Φ' V √μ,  (μ, V) the three largest eigenpairs of −½ α' (symmetrised), so X Xᵀ ≈ B.
//
// This is classical MDS with area weights (the double centring of a mesh's continuous MDS); its form differs
// from canon/classical_mds.h's uniform-weight one only by the sampling density of the mesh. Cost: the k
// eigenpairs, L single-source geodesics, O(L n k) for the fit; memory O((L + k) n).
#pragma once

#include <vector>

#include "cshapes/operators/laplace_beltrami.h"
#include "cshapes/support/option_fields.h"
#include "cshapes/support/option_limits.h"

namespace cshapes {

namespace spectral_mds_limits {
inline constexpr Limit kLandmarks = integer_limit("sources", 10, 100000);
}  // namespace spectral_mds_limits

struct SpectralMdsOptions {
  // k: the basis (the constant included). 40: the smooth part of the geodesic distance of a TOSCA shape
  // (its first 40 eigenfunctions resolve features of ~1/6 of the shape's length).
  LaplaceBeltramiOptions laplacian = [] {
    LaplaceBeltramiOptions l;
    l.eigenpairs = 40;
    return l;
  }();
  // L: geodesic rows (farthest-point sources). 3k: the fit of α needs L ≥ k rows, and a margin keeps Φ_S
  // well conditioned.
  Index sources = 120;

  // Every field by name, for cache keys (support/option_fields.h).
  template <class Self, class Visit>
  static void for_each_field(Self& o, Visit&& visit) {
    visit("laplacian", o.laplacian);
    visit("sources", o.sources);
  }
};

struct SpectralMdsResult {
  Points X;                    // n × 3
  Eigen::Vector3d eigenvalues;  // μ_1 ≥ μ_2 ≥ μ_3 of −½ α'
  double negative_mass = 0;    // −Σ of the negative eigenvalues of −½ α' over Σ |eigenvalues|: non-Euclidean share
  double fit_residual = 0;     // ‖Φ_S α Φᵀ − D²_S‖ / ‖D²_S‖ (M-weighted): what the basis misses
};

// rows: L × n geodesic distances from the vertices `sources` (geodesics/landmark_geodesics.h); eigen: at least 4
// eigenpairs, M-orthonormal. Throws when L < k or the sizes disagree.
SpectralMdsResult spectral_mds(const LaplaceBeltramiEigen& eigen, const std::vector<int>& sources,
                               const Eigen::MatrixXf& rows);

}  // namespace cshapes
