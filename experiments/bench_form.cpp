#include "cshapes/experiments/bench_form.h"

#include <omp.h>

#include <algorithm>
#include <cmath>

#include "cshapes/canon/landmark_mds.h"
#include "cshapes/support/error.h"
#include "cshapes/support/timing.h"
#include "cshapes/experiments/bench_support.h"
#include "cshapes/pipeline/canonical_form_methods.h"
#include "cshapes/pipeline/canonical_forms.h"

namespace cshapes {

namespace {

// The benchmark's options of a form: the library's defaults, with the experiments' heat geodesics (the MDS
// methods' and spectral-mds's rows), as `experiment paper` computes them.
CanonicalFormOptions form_options(const std::string& method, const std::string& source) {
  CanonicalFormOptions o = experiment_canonical_form_options();
  o.method = method;
  o.name = source;
  return o;
}

}  // namespace

FormBenchResult bench_form(const FormBenchOptions& options) {
  CSHAPES_REQUIRE(options.repeats >= 1, "--repeats must be >= 1, got ", options.repeats);
  require_canonical_form_methods({options.method}, "--method");
  FormBenchResult result;
  result.options = options;
  const Mesh mesh = bench_mesh(options.mesh, options.n, result.source);
  result.vertices = mesh.num_vertices();
  result.threads = omp_get_max_threads();
  result.rss_before_mb = peak_rss_mb();
  CanonicalFormOptions o = form_options(options.method, result.source);
  if (!options.mds_solver.empty()) {
    CSHAPES_REQUIRE(canonical_form_method(options.method).uses_geodesic_matrix,
                    "--mds-solver applies to the MDS methods (cmds, smacof), not ", options.method);
    o.mds_solver.solver = parse_mds_solver(options.mds_solver);
  }
  std::vector<double> seconds, precompute_seconds;
  for (int r = 0; r < options.repeats; ++r) {
    const auto start = WallClock::now();
    const CanonicalForm form = canonical_form(mesh, o);
    seconds.push_back(seconds_since(start));
    precompute_seconds.push_back(form.precompute_seconds);
    const nlohmann::json summary = form_summary_json(form);
    result.details = nlohmann::json::object();
    for (const auto& [key, value] : summary.items())
      if (value.is_primitive() && !value.is_null()) result.details[key] = value;
    if (form.iterations > 0) result.details["iterations"] = form.iterations;
    result.quality = summary.contains("form_quality")
                         ? summary["form_quality"].value("description", std::string("not measured"))
                         : "not measured";
  }
  result.seconds = median(seconds);
  result.precompute_seconds = median(precompute_seconds);
  result.peak_rss_mb = peak_rss_mb();
  if (!options.reference) {
    result.reference_skipped = "not asked for (--reference none)";
    return result;
  }
  CanonicalFormOptions ref = form_options("cmds", result.source);
  ref.mds_solver.solver = MdsSolver::Full;
  try {
    const auto start = WallClock::now();
    canonical_form(mesh, ref);
    result.reference_seconds = seconds_since(start);
    result.reference_ran = true;
    result.reference_peak_rss_mb = peak_rss_mb();
  } catch (const Error& error) {  // its n × n matrix does not fit: said, not the benchmark's failure
    result.reference_skipped = error.what();
  }
  return result;
}

nlohmann::json to_json(const FormBenchResult& r) {
  nlohmann::json reference;
  if (r.reference_ran)
    reference = {{"method", "cmds, full (all-pairs heat geodesics, Lanczos)"},
                 {"seconds", r.reference_seconds},
                 {"peak_rss_mb", r.reference_peak_rss_mb}};
  else
    reference = {{"skipped", r.reference_skipped}};
  nlohmann::json j = {
      {"benchmark", "form"},
      {"method", r.options.method},
      {"mds_solver", r.options.mds_solver.empty() ? "auto" : r.options.mds_solver},
      {"source", r.source},
      {"vertices", r.vertices},
      {"repeats", r.options.repeats},
      {"threads", r.threads},
      {"load_average", load_average()},
      {"seconds", r.seconds},
      {"precompute_seconds", r.precompute_seconds},
      {"quality", r.quality},
      {"details", r.details},
      {"rss_before_mb", r.rss_before_mb},
      {"peak_rss_mb", r.peak_rss_mb},
      {"reference", reference},
      {"note",
       "one canonical form with the library's defaults and the experiments' heat geodesics, median of "
       "repeats; "
       "precompute_seconds: geodesics, or the Laplacian and its eigenpairs; peak RSS of the process after "
       "the "
       "forms (rss_before_mb: after reading the mesh); reference: full classical MDS once, after the forms"}};
  if (r.reference_ran) j["speedup_vs_reference"] = r.reference_seconds / r.seconds;
  j["build"] = build_json();
  return j;
}

}  // namespace cshapes
