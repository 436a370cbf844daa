// Method lbo (pipeline/canonical_form_methods.h): the Laplace–Beltrami eigenmap scaled as the Global Point
// Signature [BN03, Rus07]: √A · φ_i/√λ_i, i = 1..3 (canon/spectral_embedding.h), on the mesh's intrinsic
// Delaunay cotangent Laplacian (a point cloud: its kNN graph Laplacian).
#include "cshapes/support/timing.h"
#include "cshapes/pipeline/canonical_form_methods.h"
#include "cshapes/pipeline/spectral_method.h"

namespace cshapes {

namespace {

CanonicalForm lbo_compute(const Mesh& mesh, const CanonicalFormOptions& options, const GivenDistances&) {
  SpectralSolve s = spectral_eigenpairs(mesh, options.lbo.laplacian, options, "lbo");
  CanonicalForm form;
  form.precompute_seconds = s.seconds;
  auto start = WallClock::now();
  form.X = gps_embedding(s.eigen, 3);
  form.solve_seconds = seconds_since(start);
  s.summary["embedding"] = "gps: sqrt(area) * phi_i / sqrt(lambda_i), i = 1..3";
  form.details = std::move(s.summary);
  return form;
}

}  // namespace

CanonicalFormMethod lbo_method() {
  CanonicalFormMethod m = spectral_method_base("lbo");
  m.title = "LBO eigenmap";
  m.summary = "Laplace-Beltrami eigenmap (GPS): sqrt(area) * phi_i / sqrt(lambda_i), i = 1..3";
  m.compute = lbo_compute;
  m.options = {laplacian_option(), eigenpairs_option(), near_multiple_gap_option()};
  m.reads = {"lbo"};
  return m;
}

}  // namespace cshapes
