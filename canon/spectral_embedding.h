// Spectral canonical forms: embeddings of a shape by its Laplace–Beltrami eigenpairs (operators/laplace_beltrami.h)
// — the alternatives to MDS the paper's introduction names (Belkin & Niyogi [BN03], Coifman & Lafon [CL06],
// Rustamov's GPS [Rus07]). Both are isometry-invariant up to the eigenvectors' signs and, within an eigenspace
// of a multiple eigenvalue, a rotation: both rigid motions (reflections) of the form, which the ICP that
// compares forms undoes (matching/icp.h: every sign combination of the principal axes is a start).
//
//   gps        x_i = √A · φ_i / √λ_i, i = 1, 2, 3 (the constant φ_0 skipped): the eigenmap scaled as
//              Rustamov's Global Point Signature, whose distances approximate the Green's-function
//              ("commute-time") distance; φ_i/√λ_i is dimensionless, so the factor √A (A the surface area,
//              an isometry invariant) gives it the mesh's units and lets it grow with the shape as MDS forms
//              do. On the unit sphere it is the sphere scaled by √(3/2).
//   diffusion  x_i = κ · e^{−λ_i t} φ_i, i = 1, 2, 3: the diffusion map at time t [CL06], whose Euclidean
//              distances are the diffusion distances d_t(x, y)² = Σ_{i≥1} e^{−2λ_i t} (φ_i(x) − φ_i(y))²
//              truncated to three terms, times one constant κ = √A · e^{λ_1 t} / √λ_1 (isometry-invariant,
//              a length): it makes the first axis the GPS form's and puts the form in the mesh's units.
//              t = c / λ_1 makes the form scale-free (a shape scaled by s has λ/s², t·s²): only the
//              dimensionless c is chosen (DiffusionFormOptions::time).
//
// Why the diffusion map and not classical MDS of diffusion distances: with area weights the double-centred
// Gram matrix of the diffusion distances has exactly the eigenvectors e^{−λ_i t} φ_i (the φ_i are
// M-orthogonal to the constant), so its top three coordinates ARE the diffusion map's — the same form, for
// O(n) memory instead of an n×n matrix (uniform weights differ only by the mesh's sampling density).
#pragma once

#include "cshapes/operators/laplace_beltrami.h"
#include "cshapes/support/option_fields.h"
#include "cshapes/support/option_limits.h"

namespace cshapes {

namespace spectral_limits {
inline constexpr Limit kDiffusionTime = number_limit("diffusion-time", 1e-3, 100);
}  // namespace spectral_limits

struct LboFormOptions {
  LaplaceBeltramiOptions laplacian;

  // Every field by name, for cache keys (support/option_fields.h).
  template <class Self, class Visit>
  static void for_each_field(Self& o, Visit&& visit) {
    visit("laplacian", o.laplacian);
  }
};

struct DiffusionFormOptions {
  LaplaceBeltramiOptions laplacian;
  // c in t = c / λ_1. 1: the slowest non-constant mode has decayed by 1/e, so heat has spread over the
  // whole shape (the distances are global, as geodesics are), and modes with λ ≥ 4λ_1 are damped by e^{-3}
  // or more relative to it, so three axes keep most of the diffusion distance (the form's summary reports
  // the fraction kept among the computed eigenpairs: 96.6-99.8% on TOSCA cat0, dog0, michael0, victoria0).
  // Smaller c: more local, more of the distance in the dropped axes; larger c: the second and third axes
  // shrink towards a line.
  double time = 1.0;

  // Every field by name, for cache keys (support/option_fields.h).
  template <class Self, class Visit>
  static void for_each_field(Self& o, Visit&& visit) {
    visit("laplacian", o.laplacian);
    visit("time", o.time);
  }
};

// The GPS form (see above) of the first `dims` non-constant eigenpairs (eigen has at least dims + 1).
Points gps_embedding(const LaplaceBeltramiEigen& eigen, int dims = 3);
// The diffusion map e^{−λ_i t} φ_i, i = 1..dims (unscaled: its distances are the truncated diffusion
// distances).
Eigen::MatrixXd diffusion_map(const LaplaceBeltramiEigen& eigen, double t, int dims);
// t = c / λ_1 (throws when λ_1 is not positive: several components).
double diffusion_time(const LaplaceBeltramiEigen& eigen, double c);
// The diffusion form (see above): κ · diffusion_map(eigen, t, 3).
Points diffusion_embedding(const LaplaceBeltramiEigen& eigen, double t);
// κ = √A e^{λ_1 t} / √λ_1: the diffusion form's distances divided by κ are diffusion distances.
double diffusion_form_scale(const LaplaceBeltramiEigen& eigen, double t);
// Σ_{i=1..3} e^{−2λ_i t} / Σ_{i≥1} e^{−2λ_i t} over the computed eigenpairs: the share of the mean squared
// diffusion distance the three axes keep (an upper bound: the uncomputed terms would add to the
// denominator).
double diffusion_energy_kept(const LaplaceBeltramiEigen& eigen, double t);

}  // namespace cshapes
