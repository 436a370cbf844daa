// The spectral canonical forms' benchmark (`cshapes bench spectral`): seconds and peak memory of one form by
// method lbo, diffusion or spectral-mds (pipeline/method_lbo.cpp, method_diffusion.cpp, method_spectral_mds.cpp)
// on a mesh, the median over
// `repeats` forms, with the parts: the Laplacian and its eigenpairs (precompute) and the embedding (solve).
// Memory is the process's peak resident set (getrusage) after the forms, beside its value before them (the
// mesh read): run one method per process for a per-method figure.
#pragma once

#include <nlohmann/json.hpp>
#include <string>

#include "core/types.h"

namespace cshapes {

struct SpectralBenchOptions {
  std::string mesh;               // mesh file; "": a torus of about n vertices
  int n = 5000;                   // vertices of the generated torus, >= 16
  std::string method = "lbo";     // lbo, diffusion or spectral-mds (its rows: heat geodesics)
  int repeats = 3;                // forms timed (median reported), >= 1
};

struct SpectralBenchResult {
  SpectralBenchOptions options;  // as run
  std::string source;            // the mesh file, or "torus NUxNV"
  Index vertices = 0;
  int threads = 0;
  double seconds = 0;             // one form, median (canonical_form: repair check, eigenpairs, embedding)
  double eigen_seconds = 0;       // its Laplacian and eigenpairs, and spectral-mds's rows (precompute), median
  Index operator_products = 0;    // shift-invert products of the last form
  std::string solver;             // of the last form
  double rss_before_mb = 0;       // peak resident memory before the first form (mesh read)
  double peak_rss_mb = 0;         // after the forms
};

SpectralBenchResult bench_spectral(const SpectralBenchOptions& options);

// {benchmark: "spectral", method, source, vertices, repeats, threads, seconds, eigen_seconds,
//  operator_products, solver, rss_before_mb, peak_rss_mb, note}.
nlohmann::json to_json(const SpectralBenchResult& result);

}  // namespace cshapes
