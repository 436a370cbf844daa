// MDS canonical forms from L landmark rows of the distance matrix (L × n memory instead of n × n): landmark
// classical MDS (de Silva & Tenenbaum, "Sparse multidimensional scaling using landmark points", 2004; one of
// the Nyström methods Platt compares in [Pla05]) and SMACOF on the landmarks with the other points
// interpolated. The rows come from geodesics/landmark_geodesics.h (farthest-point landmarks).
//
// Landmark classical MDS. Δ the L×L squared distances between landmarks (the rows' landmark columns,
// symmetrised), δ_μ its column means, B_L = −½ J Δ J its double centring (canon/classical_mds.h with n = L):
//   landmarks:   Y = [v₁ v₂ v₃] diag(√λ₁, √λ₂, √λ₃)      (the classical MDS of the landmarks)
//   every point: x_a = −½ L^# (δ_a − δ_μ),   L^# = diag(1/√λ) [v₁ v₂ v₃]ᵀ   (distance-based triangulation)
// with δ_a the squared distances from point a to the landmarks. A landmark is placed at its own Y row, and
// with every vertex a landmark (L = n) the result is classical MDS of the full matrix (up to the signs of
// the axes); the form is then centred at the mean of all points. Axes with λ ≤ 0 are zero.
//
// Landmark SMACOF. SMACOF (canon/smacof.h) of the L×L block from the landmarks' classical MDS, then each
// other point placed against the fixed landmarks: started beside its nearest landmark y_n, at distance δ_an,
// in the direction of the least-squares triangulation in the SMACOF frame (‖x − y_k‖² ≈ δ²_ak linearised by
// subtracting the landmarks' mean: 2 (y_k − ȳ)·x ≈ ‖y_k‖² − δ²_ak − mean), then moved by
// `interpolation_iterations` Guttman transforms of its own stress Σ_k w_k (δ_ak − ‖x − y_k‖)² with the
// landmarks held (x⁺ = Σ_k w_k [y_k + δ_ak (x − y_k)/‖x − y_k‖] / Σ_k w_k, which never increases it).
// Folds. A point's stress against the landmarks can have two basins: on a thin part (an arm, a finger) the
// near landmarks lie along its axis and fix only the point's distance from it, so a point near such a fold
// can settle across it, away from its mesh neighbours (measured on tosca5k michael0 at 5,000 vertices,
// L = 300: 20 vertices on edges stretched up to 33×; started at the triangulation itself 7 vertices, with
// weights 1/δ² none but a mean stretch of 1.18). Given the input's edge graph (LandmarkNeighbourGraph), the
// interpolation is repaired: edges longer than `overstretch` × max(their input length, the mean input length)
// are cut, and in each component of the input graph the points outside the largest remaining part are
// placed again, layer by layer from that part (breadth first), each started at the mean of its neighbours
// already placed and moved by the same Guttman transforms, but kept within half its mean input edge length
// of that start (each step projected onto the ball: the stress still never increases): the point stays
// beside its neighbours, at the best place there. Up to `rounds` rounds, while the cut edges cut a part
// off. Landmarks in a cut-off part are placed again too (their interpolated rows; the landmarks' SMACOF
// itself is kept). The repair is kept only when it leaves fewer edges over the limit than the interpolation
// did. A fold that cuts nothing off (a crease inside a part: both sides stay connected around its ends) is
// not repaired: placing its ends again between the two sheets made it worse (KIDS, 60,000 vertices).
// Landmark weights w_k: uniform,
// or (SmacofOptions::vertex_weights given, n values) the sum of the weights of the vertices nearest to
// landmark k (its geodesic Voronoi cell), so area weights stay area weights.
//
// Cost: O(L·n) memory for the rows (read only), O(L²) for the block; O(L³) for the dense eigensolver of the
// block; O(L·n) for the triangulation, O(L·n·iterations) for the interpolation (OpenMP over points); SMACOF
// on the block O(L²) per pass. Rows must be finite and ≥ 0 (throws naming the entry), L ≥ 4.
#pragma once

#include <string>
#include <vector>

#include "cshapes/canon/smacof.h"
#include "cshapes/support/option_fields.h"
#include "cshapes/support/option_limits.h"
#include "cshapes/support/types.h"

namespace cshapes {

namespace landmark_limits {
// 0 (no repair) or above 1 (a limit below an edge's own length would cut every edge).
inline constexpr Limit kFoldOverstretch = number_limit("fold-overstretch", 0, 1000);
// L of landmark MDS (farthest-point sampling; clamped to n).
inline constexpr Limit kLandmarks = integer_limit("mds-landmarks", 4, 1e6);
}  // namespace landmark_limits

// Which solver an MDS canonical form uses: the full n×n matrix, L landmark rows, or the rule of auto
// (mds_uses_landmarks).
enum class MdsSolver { Full, Landmarks, Auto };
// Parses "full", "landmarks", "auto"; throws listing them otherwise.
MdsSolver parse_mds_solver(const std::string& name);
std::string to_string(MdsSolver solver);
const std::vector<std::string>& mds_solver_names();

struct MdsSolverOptions {
  MdsSolver solver = MdsSolver::Auto;  // auto: full matrix up to auto_full_max_vertices, landmarks beyond
  Index landmarks = 300;               // L, landmarks by farthest-point sampling (clamped to n)
  // auto: landmarks above this many vertices (the full path then needs ≥ 0.58 GB and minutes:
  // docs/benchmarks.md), or whenever n² floats would take more than half the memory this process may still
  // use.
  Index auto_full_max_vertices = 12000;
  int interpolation_iterations = 30;  // smacof on landmarks: Guttman steps of each other point
  // smacof on landmarks: edges longer than this × max(input length, mean input length) mark points
  // interpolated across a fold, placed again from their neighbours (LandmarkNeighbourGraph); 0: no repair.
  double fold_overstretch = 3.0;

  // Every field by name, for cache keys (support/option_fields.h). Self: MdsSolverOptions, const or not.
  template <class Self, class Visit>
  static void for_each_field(Self& o, Visit&& visit) {
    visit("solver", o.solver);
    visit("landmarks", o.landmarks);
    visit("auto_full_max_vertices", o.auto_full_max_vertices);
    visit("interpolation_iterations", o.interpolation_iterations);
    visit("fold_overstretch", o.fold_overstretch);
  }
};

// Whether `options` embed n points from landmark rows: Landmarks always, Full never, Auto when n >
// auto_full_max_vertices or when n² floats exceed half of `available_bytes` (< 0: unknown, not a reason).
bool mds_uses_landmarks(const MdsSolverOptions& options, Index n, double available_bytes);

// The input's edge graph, for landmark SMACOF's fold repair (see "Folds" above).
struct LandmarkNeighbourGraph {
  Edges edges;               // |E|×2 point indices (mesh edges or the kNN graph); empty: no repair
  Eigen::VectorXd lengths;   // |E| input lengths, in the units of the rows
  double overstretch = 3.0;  // an edge longer than this × max(its length, the mean length) is cut
  int rounds = 10;           // repair rounds at most
};

struct LandmarkMdsResult {
  Points X;                     // n×3, centred at the mean of the points, units of the distances
  Eigen::Vector3d eigenvalues;  // λ₁ ≥ λ₂ ≥ λ₃ of the landmarks' B_L
  double explained_energy = 0;  // (λ₁² + λ₂² + λ₃²) / ‖B_L‖²_F
  // Landmark SMACOF only (NaN otherwise): the landmarks' normalised stress after SMACOF, and the mean over
  // the other points of their stress against the landmarks, Σ_k w_k (δ_ak − d_ak)² / Σ_k w_k δ_ak², at the
  // start (beside the nearest landmark) and after the interpolation steps.
  double landmark_normalized_stress = std::numeric_limits<double>::quiet_NaN();
  double start_point_stress = std::numeric_limits<double>::quiet_NaN();
  double interpolated_point_stress = std::numeric_limits<double>::quiet_NaN();
  SmacofResult landmark_smacof;  // SMACOF of the landmark block (empty for classical)
  // Landmark SMACOF with a graph: points placed again from their neighbours, rounds run, and edges still
  // over the limit after the last one.
  Index replaced_points = 0;
  int repair_rounds = 0;
  Index overstretched_edges = 0;
  bool repair_kept = true;  // false: the repair left no fewer edges over the limit, and was undone
  double seconds = 0;
};

// Landmark classical MDS. rows: L × n distances from landmarks[k] to every point (landmarks[k] < n,
// distinct).
LandmarkMdsResult landmark_classical_mds(const Eigen::MatrixXf& rows, const std::vector<int>& landmarks);
// The same from double rows (a name of its own: a float expression would convert to either): no rounding of
// the distances to float, so that the embedding follows its input to double precision (the Coulomb start,
// canon/coulomb_start.h).
LandmarkMdsResult landmark_classical_mds_double(const Eigen::MatrixXd& rows, const std::vector<int>& landmarks);

// Landmark SMACOF: `smacof` runs on the landmark block (its vertex_weights: empty, or n per-point weights
// summed over each landmark's Voronoi cell) from `start` (L×3, e.g. the mesh's landmark vertices; empty:
// the landmarks' classical MDS); interpolation_iterations as above.
// graph: the input's edges and their lengths (empty: no fold repair; see "Folds" above).
LandmarkMdsResult landmark_smacof(const Eigen::MatrixXf& rows, const std::vector<int>& landmarks,
                                  const SmacofOptions& smacof, int interpolation_iterations = 30,
                                  const Points& start = {}, const LandmarkNeighbourGraph& graph = {});

}  // namespace cshapes
