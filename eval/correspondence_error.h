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
// Geodesics: one single-source run per distinct true vertex among the samples used (geodesics/geodesics.h,
// options.geodesics: by default Dijkstra on B's edges, an upper bound of the surface distance, a few
// percent long), or read from a given all-pairs matrix. Cost without the matrix: O(S · n log n) for S samples
// (1,000 samples on 5,000 vertices: ~0.5 s on one core), OpenMP over samples.
#pragma once

#include <string>
#include <vector>

#include "cshapes/support/distance_matrix.h"
#include "cshapes/geodesics/geodesics.h"
#include "cshapes/mesh/mesh.h"

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

// ---- SHREC'16 ground truth (TOPKIDS): vertex pairs, and errors with a forgiven symmetric flip
// ----------------

// A ground-truth correspondence file of SHREC'16 "Topological KIDS" (shared/data/topkids/kidNN_ref.txt and
// kidNN_sym.txt): one line per listed vertex, two 1-based integers "a b": vertex a of the query shape A
// corresponds to vertex b of the reference B. kidNN_sym.txt has the same form but both columns are vertices
// of A: b is a's left-right mirror on A itself, so a's mirrored truth on B is ref(b) (not b read as a vertex
// of B, which lies far from the mirror: docs/design.md, "Measured figures behind choices in the code"). Not every vertex of A need be listed; a vertex of A listed twice is refused (its truth
// would be ambiguous). Blank lines are skipped.
struct CorrespondencePairs {
  std::vector<int> from;  // 0-based vertices of A, in the file's order
  std::vector<int> to;    // 0-based vertices of B, to[k] for from[k]
};

// Throws naming the file and line on a line that is not exactly two integers, an index < 1, an index beyond
// a_vertices / b_vertices (when those are > 0), a vertex of A listed twice (naming both lines), or a file
// with no pair.
CorrespondencePairs read_correspondence_pairs(const std::string& path, Index a_vertices = 0,
                                              Index b_vertices = 0);

// Errors of several maps A → B against one ground truth, by the SHREC'16 protocol: for each ground-truth
// vertex a of A used, the geodesic distance on B between map(a) and truth(a), over √area(B); where a has a
// symmetric truth sym(a) ≥ 0, the smaller of that and the distance to sym(a) (a left-right flip is forgiven).
//
// maps[i]: for every vertex of A, a vertex of B, or −1 where the map gives none (e.g. a vertex dropped from a
// canonical form): such a sample counts as unmapped — never under any threshold, left out of the mean.
// truth_a / truth_b / symmetric_b: equal lengths; symmetric_b[s] = −1 where there is no mirrored truth
// (an empty symmetric_b: none anywhere). Samples: options.max_samples evenly spaced over the list (≤ 0: all).
//
// Geodesics on B: B is first repaired to a manifold surface (mesh/mesh_repair.h: largest component,
// non-manifold vertices split, zero-area faces dropped) and distances are placed back at B's vertices; a
// sample whose true vertex the repair dropped is skipped (counted in skipped_samples). One single-source run
// (options.geodesics) per distinct true or symmetric vertex serves every map, so scoring k maps costs about
// what scoring one does: O(S · n log n) for S samples with fast marching (its stencils built once), OpenMP
// over sources. The area is that of the repaired B (duplicate faces counted once).
struct SymmetricCorrespondenceErrorResult {
  std::vector<CorrespondenceErrorResult> maps;  // per map: errors (+inf where unmapped), curve, mean, median
  std::vector<int> unmapped;                    // per map: samples whose vertex of A has no image (−1)
  std::vector<int> symmetric_chosen;            // per map: samples whose error came from the mirrored truth
  // Per map, per sample (normalised, +inf where unmapped): the error against the truth alone, and against the
  // mirrored truth where there is one (the truth elsewhere). Scoring a whole map by the better of the two
  // (Kim, Lipman & Funkhouser 2011) forgives a flip of the whole shape but not a map that mixes the sides,
  // which the per-sample minimum above forgives too: a map unrelated to the truth has about half its
  // samples nearer the mirrored vertex.
  std::vector<Eigen::VectorXd> direct_errors, mirrored_errors;
  int skipped_samples = 0;  // true vertex dropped by B's repair (not in the results)
  std::string repair_text;  // what the repair of B did ("" when nothing)
};

SymmetricCorrespondenceErrorResult symmetric_correspondence_errors(
    const Mesh& b, const std::vector<Eigen::VectorXi>& maps, const std::vector<int>& truth_a,
    const std::vector<int>& truth_b, const std::vector<int>& symmetric_b,
    const CorrespondenceErrorOptions& options = {}, const std::string& b_name = "B");

// Statistics of a vector of per-sample errors, +inf where a sample is unmapped (as in the results above).
// The mean over the finite entries, in order; NaN when there is none.
double finite_mean(const Eigen::VectorXd& errors);
// The median over all entries (+inf counts): the middle value, or the mean of the two middle values for an
// even count (so, unlike support/timing.h's median of repeats, not always one of the entries); NaN when empty.
double error_median(Eigen::VectorXd errors);
// The fraction of all entries ≤ threshold (an unmapped sample never is); 0 when empty.
double fraction_within(const Eigen::VectorXd& errors, double threshold);

}  // namespace cshapes
