// Method diffusion (pipeline/canonical_form_methods.h): the diffusion map [CL06] at time t = c/λ_1, c =
// options.diffusion.time (scale-free: relative to the shape's own spectrum), scaled into the mesh's units
// (canon/spectral_embedding.h).
#include "cshapes/support/format.h"
#include "cshapes/support/timing.h"
#include "cshapes/pipeline/canonical_form_methods.h"
#include "cshapes/pipeline/spectral_method.h"

namespace cshapes {

namespace {

CanonicalForm diffusion_compute(const Mesh& mesh, const CanonicalFormOptions& options, const GivenDistances&) {
  SpectralSolve s = spectral_eigenpairs(mesh, options.diffusion.laplacian, options, "diffusion");
  CanonicalForm form;
  form.precompute_seconds = s.seconds;
  auto start = WallClock::now();
  const double t = diffusion_time(s.eigen, options.diffusion.time);
  form.X = diffusion_embedding(s.eigen, t);
  form.solve_seconds = seconds_since(start);
  const double kept = diffusion_energy_kept(s.eigen, t);
  s.summary["embedding"] = "diffusion map: kappa * exp(-lambda_i t) * phi_i, i = 1..3";
  s.summary["time_factor"] = options.diffusion.time;
  s.summary["time"] = t;
  s.summary["scale"] = diffusion_form_scale(s.eigen, t);
  s.summary["energy_kept"] = kept;
  say(options.note, "diffusion: t = " + significant(options.diffusion.time) + "/λ1 = " + significant(t) +
                        "; 3 axes keep " + significant(100 * kept) +
                        "% of the mean squared diffusion distance (of the computed eigenpairs)");
  form.details = std::move(s.summary);
  return form;
}

}  // namespace

CanonicalFormMethod diffusion_method() {
  CanonicalFormMethod m = spectral_method_base("diffusion");
  m.title = "diffusion map";
  m.summary = "diffusion map exp(-lambda_i t) phi_i at t = c / lambda_1 (scale-free), in the mesh's units";
  m.compute = diffusion_compute;
  m.options = {laplacian_option(), eigenpairs_option(), near_multiple_gap_option(),
               number_option("diffusion_time", "c in t = c / lambda_1", spectral_limits::kDiffusionTime,
                             {"diffusion"}, [](CanonicalFormOptions& c) -> double& { return c.diffusion.time; })};
  m.reads = {"diffusion"};
  return m;
}

}  // namespace cshapes
