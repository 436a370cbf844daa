// One canonical form's benchmark (`cshapes bench form`): seconds and peak memory of one form by any registered
// method (pipeline/canonical_form_methods.h) on a mesh, the median over `repeats` forms, with its
// precomputation (geodesics, eigenpairs) apart; and, in the same run, the reference every canonical form is
// an alternative to: full classical MDS of all-pairs heat geodesics (the paper's MDS, our fastest full path),
// so the row's ratio is that form's speed-up over it.
//
// Memory is the process's peak resident set (getrusage): before the forms (the mesh read), after them, and
// after the reference (which runs last, so that it cannot raise the forms' figure). Run one method per process
// for a per-method figure. A reference that cannot run (its n × n matrix does not fit, or --reference none)
// is reported as skipped, with the reason.
#pragma once

#include <nlohmann/json.hpp>
#include <string>

#include "cshapes/support/types.h"

namespace cshapes {

struct FormBenchOptions {
  std::string mesh;               // mesh file; "": a torus of about n vertices
  int n = 5000;                   // vertices of the generated torus, >= 16
  std::string method =
      "coulomb";                  // a registered method (coulomb, cmds, smacof, lbo, diffusion, spectral-mds)
  std::string mds_solver;         // cmds, smacof: full, landmarks or auto; "": the library's default (auto)
  int repeats = 3;                // forms timed (median reported), >= 1
  bool reference = true;          // also time full classical MDS of heat geodesics once
};

struct FormBenchResult {
  FormBenchOptions options;  // as run
  std::string source;        // the mesh file, or "torus NUxNV"
  Index vertices = 0;
  int threads = 0;
  double seconds = 0;             // one form, median (canonical_form: repair check, precompute, solve, quality)
  double precompute_seconds = 0;  // its geodesics or Laplacian and eigenpairs, median
  std::string quality;            // the last form's quality verdict ("ok: …" or "not ok: …")
  nlohmann::json details;         // from the last form's summary: solver, products, landmarks, iterations…
  double rss_before_mb = 0;       // peak resident memory before the first form (mesh read)
  double peak_rss_mb = 0;         // after the forms
  // The reference, full classical MDS (heat all-pairs geodesics + Lanczos), once.
  bool reference_ran = false;
  std::string reference_skipped;  // why not, when not ran
  double reference_seconds = 0;
  double reference_peak_rss_mb = 0;  // the process's peak after it
};

FormBenchResult bench_form(const FormBenchOptions& options);

// {benchmark: "form", method, mds_solver, source, vertices, repeats, threads, seconds, precompute_seconds,
//  quality, details, rss_before_mb, peak_rss_mb, reference: {method, seconds, peak_rss_mb} | {skipped},
//  speedup_vs_reference (when it ran), note}.
nlohmann::json to_json(const FormBenchResult& result);

}  // namespace cshapes
