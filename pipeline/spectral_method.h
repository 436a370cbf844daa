// What the spectral methods (lbo: pipeline/method_lbo.cpp, diffusion: pipeline/method_diffusion.cpp,
// spectral-mds: pipeline/method_spectral_mds.cpp) share:
// the Laplace–Beltrami eigenpairs of the method's mesh, said and summarised once.
#pragma once

#include <nlohmann/json.hpp>
#include <string>

#include "cshapes/operators/laplace_beltrami.h"
#include "cshapes/pipeline/canonical_form_methods.h"

namespace cshapes {

struct SpectralSolve {
  LaplaceBeltramiEigen eigen;
  nlohmann::json summary;  // {laplacian, solver, eigenvalues, near_multiple, warning?, ...}
  double seconds = 0;      // the operator and the eigensolve: the form's precompute_seconds
};

// The eigenpairs of `mesh` (already repaired: one component) for a spectral method, with its notes
// (options.note): the solve, near-multiple eigenvalues, and a warning when λ_3 and λ_4 are near-multiple
// (the form's third axis is then one direction of a near-degenerate eigenspace, not set by the shape).
// A point cloud whose kNN graph falls apart is refused (its λ_1 would be 0), as method coulomb does.
SpectralSolve spectral_eigenpairs(const Mesh& mesh, const LaplaceBeltramiOptions& laplacian,
                                  const CanonicalFormOptions& options, const std::string& method);

// The registration the spectral methods share (requirements, repair purpose).
CanonicalFormMethod spectral_method_base(const std::string& name);
// Their options on the Laplace–Beltrami operator: --laplacian and --near-multiple-gap (lbo, diffusion,
// spectral-mds: set in each one's group), --eigenpairs (lbo and diffusion; spectral-mds's are its --basis).
MethodOption laplacian_option();
MethodOption eigenpairs_option();
MethodOption near_multiple_gap_option();

}  // namespace cshapes
