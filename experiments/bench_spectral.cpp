#include "experiments/bench_spectral.h"

#include <omp.h>

#include <algorithm>
#include <cmath>

#include "core/error.h"
#include "core/io.h"
#include "core/synthetic.h"
#include "core/timing.h"
#include "experiments/bench_support.h"
#include "pipeline/canonical_forms.h"

namespace cshapes {

SpectralBenchResult bench_spectral(const SpectralBenchOptions& options) {
  CSHAPES_REQUIRE(options.repeats >= 1, "--repeats must be >= 1");
  CSHAPES_REQUIRE(options.method == "lbo" || options.method == "diffusion" || options.method == "spectral-mds",
                  "--method: lbo, diffusion or spectral-mds, got '", options.method, "'");
  SpectralBenchResult result;
  result.options = options;
  Mesh mesh;
  if (!options.mesh.empty()) {
    mesh = read_mesh(options.mesh);
    result.source = options.mesh;
  } else {
    CSHAPES_REQUIRE(options.n >= 16, "--n must be >= 16, got ", options.n);
    const int nv = std::max(4, static_cast<int>(std::lround(std::sqrt(options.n / 3.0))));
    const int nu = (options.n + nv - 1) / nv;
    mesh = torus(nu, nv, 1.0, 0.3);
    result.source = "torus " + std::to_string(nu) + "x" + std::to_string(nv);
  }
  result.vertices = mesh.num_vertices();
  result.threads = omp_get_max_threads();
  result.rss_before_mb = peak_rss_mb();
  CanonicalFormOptions o;
  o.method = options.method;
  o.geodesics.method = GeodesicMethod::Heat;  // spectral-mds's rows: the experiments' geodesics
  o.name = result.source;
  std::vector<double> seconds, eigen_seconds;
  for (int r = 0; r < options.repeats; ++r) {
    const auto start = WallClock::now();
    const CanonicalForm form = canonical_form(mesh, o);
    seconds.push_back(seconds_since(start));
    eigen_seconds.push_back(form.precompute_seconds);
    const nlohmann::json summary = nlohmann::json::parse(form.summary_json);
    result.operator_products = summary.value("operator_products", Index{0});
    result.solver = summary.value("solver", std::string());
  }
  result.seconds = median(seconds);
  result.eigen_seconds = median(eigen_seconds);
  result.peak_rss_mb = peak_rss_mb();
  return result;
}

nlohmann::json to_json(const SpectralBenchResult& r) {
  return {{"benchmark", "spectral"},
          {"method", r.options.method},
          {"source", r.source},
          {"vertices", r.vertices},
          {"repeats", r.options.repeats},
          {"threads", r.threads},
          {"seconds", r.seconds},
          {"eigen_seconds", r.eigen_seconds},
          {"operator_products", r.operator_products},
          {"solver", r.solver},
          {"rss_before_mb", r.rss_before_mb},
          {"peak_rss_mb", r.peak_rss_mb},
          {"note",
           "one canonical form with the library's defaults (lbo, diffusion: 10 eigenpairs; spectral-mds: 40 and "
           "120 heat-geodesic rows; intrinsic Delaunay Laplacian), median of repeats; eigen_seconds: the "
           "precomputation (Laplacian + shift-invert eigensolve, and spectral-mds's rows); peak RSS of the "
           "process"}};
}

}  // namespace cshapes
