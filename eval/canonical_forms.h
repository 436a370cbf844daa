// Canonical forms of a mesh by any of the three methods, behind one call, and cached on disk.
//
//   coulomb  §2 of the paper (canon/coulomb.h): edge lengths only, O(n log n) per iteration
//   cmds     classical MDS (canon/classical_mds.h) of all-pairs geodesic distances
//   smacof   SMACOF (canon/smacof.h) of the same distances, initialised from classical MDS
//
// The result keeps the mesh's vertex order. Point clouds (no faces) use a symmetric kNN graph for the
// Coulomb constraints and for graph geodesics. The cache key is the mesh's content (coordinates and faces)
// plus every option that changes the result (canonical_form_key), so a cached form is never stale and a
// killed run resumes without recomputing finished shapes.
#pragma once

#include <string>
#include <vector>

#include "canon/classical_mds.h"
#include "canon/coulomb.h"
#include "canon/smacof.h"
#include "core/geodesics.h"
#include "core/knn_graph.h"
#include "core/mesh.h"
#include "eval/cache.h"

namespace cshapes {

struct CanonicalFormOptions {
  std::string method = "coulomb";  // coulomb | cmds | smacof
  CoulombCanonOptions coulomb;     // method coulomb (its defaults are the measured ones, see README)
  // MDS: the geodesics behind them. Fast marching, as the paper used [KS98].
  GeodesicOptions geodesics = [] {
    GeodesicOptions g;
    g.method = GeodesicMethod::FastMarching;
    return g;
  }();
  ClassicalMdsOptions cmds;  // method cmds, and the initialisation of smacof
  SmacofOptions smacof;      // method smacof
  KnnGraphOptions knn;       // point clouds: the graph that stands in for mesh edges
  ProgressFn progress;       // stages "geodesics", "coulomb"
};

// Every method name canonical_form accepts.
const std::vector<std::string>& canonical_form_methods();

struct CanonicalForm {
  Points X;                     // n×3, the mesh's vertex order
  Eigen::VectorXd torn;         // coulomb: 1 for vertices of torn edges, else 0; empty for MDS
  double precompute_seconds = 0;  // geodesics (MDS) or edge lengths and graph (coulomb)
  double solve_seconds = 0;       // the embedding itself
  int iterations = 0;
  double seconds_per_iteration = 0;
  // Per-iteration history as columns (coulomb: energy, mean_violation, ...; smacof: normalized_stress).
  std::vector<std::string> history_columns;
  std::vector<std::vector<double>> history_rows;
  std::string summary_json;  // method-specific summary (eigenvalues, stress, stop reason, ...)
};

// Computes the canonical form. D: optional precomputed all-pairs distances for MDS (n×n), reused instead
// of computing geodesics (e.g. one matrix shared by cmds and smacof); D_seconds: what computing it took,
// reported as the form's precompute_seconds.
CanonicalForm canonical_form(const Mesh& mesh, const CanonicalFormOptions& options,
                             const DistanceMatrix* D = nullptr, double D_seconds = 0);

// The part of the cache key that depends on the options: every field that changes the result.
std::string canonical_form_key(const CanonicalFormOptions& options);
// Content key of a mesh: SHA-256 of its coordinates and faces.
std::string mesh_content_key(const Mesh& mesh);

// canonical_form through a DiskCache (a disabled cache computes every time). *was_cached tells which.
// The cache key of that form.
CanonicalForm cached_canonical_form(const DiskCache& cache, const Mesh& mesh, const CanonicalFormOptions& options,
                                    bool* was_cached = nullptr, const DistanceMatrix* D = nullptr,
                                    double D_seconds = 0);
std::string canonical_form_cache_key(const Mesh& mesh, const CanonicalFormOptions& options);

}  // namespace cshapes
