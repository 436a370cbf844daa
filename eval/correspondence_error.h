// Quality of a point-to-point map between two shapes against ground truth: the cumulative geodesic-error
// curve of Kim, Lipman & Funkhouser (2011) — for each error threshold, the fraction of ground-truth samples
// mapped within it.
//
// Ground truth (TOSCA, shared/data/tosca5k/corres/NAME.vts): sample s is vertex vts_A[s] of A and vertex
// vts_B[s] of B. A map m: vertices of A → vertices of B (e.g. IcpResult::source_to_target after aligning the
// canonical forms of A and B, whose rows are the meshes' vertices) sends sample s to m(vts_A[s]); its error
// is the geodesic distance on B from there to vts_B[s], divided by √area(B) (so errors are comparable
// across shapes and scales; 0.25 is a quarter of the shape's "size").
//
// Geodesics: one single-source run per distinct true vertex among the samples used (core/geodesics.h,
// options.geodesics: by default Dijkstra on B's edges, an upper bound of the surface distance, a few
// percent long), or read from a given all-pairs matrix. Cost without the matrix: O(S · n log n) for S samples
// (1,000 samples on 5,000 vertices: ~0.5 s on one core), OpenMP over samples.
#pragma once

#include <string>
#include <vector>

#include "core/distance_matrix.h"
#include "core/geodesics.h"
#include "core/mesh.h"

namespace cshapes {

// Reads a .vts file: one 1-based vertex index per line (extra columns ignored). Returns 0-based indices.
// Throws naming the file and line on a non-number or an index < 1 (or > num_vertices when that is > 0).
std::vector<int> read_vts(const std::string& path, Index num_vertices = 0);

struct CorrespondenceErrorOptions {
  int max_samples = 1000;       // ground-truth samples used, evenly spaced in the file's order; ≤ 0: all
  double max_threshold = 0.25;  // largest error threshold of the curve (in units of √area(B))
  int curve_points = 101;       // thresholds 0, max/(points−1), …, max
  bool normalise = true;        // divide errors by √area(B); false: errors in B's units
  // Single-source geodesics on B when no matrix is given: Dijkstra on the edges by default (no set-up per
  // source; a few percent long). A method with per-call set-up (heat) repeats it for every source.
  GeodesicOptions geodesics = [] {
    GeodesicOptions g;
    g.method = GeodesicMethod::Graph;
    return g;
  }();
};

struct CorrespondenceErrorResult {
  std::vector<int> samples;    // the sample indices used (into the .vts lists)
  Eigen::VectorXd errors;      // per sample used, normalised as requested
  Eigen::VectorXd thresholds;  // curve_points values
  Eigen::VectorXd fraction;    // fraction of samples with error ≤ threshold (non-decreasing, in [0, 1])
  double mean_error = 0;
  double median_error = 0;
  double normaliser = 1;  // √area(B), or 1
};

// map_a_to_b: for every vertex of A, a vertex of B (0-based). truth_a, truth_b: the 0-based .vts lists of
// A and B (equal lengths). geodesics_b: B's all-pairs geodesic distances, or null to run Dijkstra.
CorrespondenceErrorResult correspondence_error(const Mesh& b, const Eigen::VectorXi& map_a_to_b,
                                               const std::vector<int>& truth_a,
                                               const std::vector<int>& truth_b,
                                               const CorrespondenceErrorOptions& options = {},
                                               const DistanceMatrix* geodesics_b = nullptr);

}  // namespace cshapes
