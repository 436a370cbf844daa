// SMACOF (de Leeuw 1977): metric multidimensional scaling to 3-D by majorisation (Guttman transforms), the
// MDS canonical form of Elad & Kimmel, with optional vector-extrapolation acceleration (Rosman, Bronstein,
// Bronstein, Sidi & Kimmel, "Fast multidimensional scaling using vector extrapolation", 2008).
//
// Stress of an embedding X (n×3) against distances δ (the n×n matrix D), over pairs i < j:
//   σ(X) = Σ_{i<j} wᵢⱼ (δᵢⱼ − dᵢⱼ(X))²,   dᵢⱼ(X) = ‖xᵢ − xⱼ‖,   wᵢⱼ = wᵢ wⱼ
// Normalised stress (what the history reports): σ(X) / Σ_{i<j} wᵢⱼ δᵢⱼ² (1 for X = 0; Guttman iterates
// stay below 1).
//
// Weights are products of positive per-vertex weights (e.g. vertex areas, so that σ approximates the
// continuous stress integral). For them the Guttman transform stays O(n) beyond the pass over D:
//   X⁺ = V⁺ B(X) X with V = s·diag(w) − w wᵀ, s = Σ w, whose pseudo-inverse on weighted-centred
//   configurations gives  x⁺ᵢ = (1/s) Σ_{j≠i} wⱼ (δᵢⱼ / dᵢⱼ) (xᵢ − xⱼ)   (terms with dᵢⱼ = 0 omitted).
// Uniform weights give the textbook X⁺ = B(X) X / n. Each transform never increases σ.
//
// Cost per iteration: ONE streaming pass over the upper triangle of D (symmetry: each pair read once and
// credited to both rows), computing B(X)X and σ(X) together. Tiles of 256×256 entries (the next rows
// prefetched), OpenMP over tiles, single-precision distance arithmetic (AVX2 when compiled for it) with float
// partial sums of at most 256 terms flushed into double accumulators. Extra memory O(n · threads). D is
// single precision, symmetric (only entries i < j are read), finite and ≥ 0: an infinite entry (disconnected
// mesh) is refused.
//
// Acceleration (RRE / MPE, "cycling mode"): from x₀, K = `extrapolation_window` Guttman steps give x₁ … x_K
// (K − 1 passes: each pass at x_k yields x_{k+1}); their K differences are combined into an extrapolated
// configuration, evaluated by one more pass. It is kept only when its stress is below the last evaluated
// Guttman iterate's (else the cycle continues from x_K), so the reported stresses never increase either.
// Iterations are counted as passes over D (the cost), including those spent on rejected extrapolations.
// Measured on tosca5k cat0 (fast-marching geodesics, from classical MDS): plain SMACOF converges
// (tolerance 1e-6) in 59 iterations; RRE reaches the same stress in 18, MPE in 17 (K = 6).
#pragma once

#include "cshapes/support/option_fields.h"
#include "cshapes/support/option_limits.h"

#include <string>
#include <vector>

#include "cshapes/support/distance_matrix.h"
#include "cshapes/mesh/mesh.h"
#include "cshapes/support/progress.h"
#include "cshapes/support/types.h"

namespace cshapes {

enum class SmacofAcceleration {
  None,  // plain Guttman transforms
  Rre,   // reduced rank extrapolation
  Mpe,   // minimal polynomial extrapolation
};
// Parses "none", "rre", "mpe"; throws listing them otherwise.
SmacofAcceleration parse_smacof_acceleration(const std::string& name);
std::string to_string(SmacofAcceleration acceleration);

// The limits of the options a user sets (support/option_limits.h), named as on the command line.
namespace smacof_limits {
inline constexpr Limit kIterations = integer_limit("smacof-max-iterations", 0, 1e8);
inline constexpr Limit kTolerance = number_limit("smacof-tolerance", 0);
inline constexpr Limit kWindow = integer_limit("smacof-window", 2, 1000);
}  // namespace smacof_limits

struct SmacofOptions {
  int max_iterations =
      300;  // passes over D after the initial one (each a Guttman transform or extrapolation)
  // Stop when the relative stress decrease (σₖ₋₁ − σₖ)/σₖ₋₁ per pass falls below this (with acceleration:
  // averaged over an extrapolation cycle); ≤ 0: never, run max_iterations.
  double tolerance = 1e-5;
  double target_stress = 0;  // also stop once the normalised stress is ≤ this (0: off)
  SmacofAcceleration acceleration = SmacofAcceleration::None;  // see the table above
  int extrapolation_window = 6;    // Guttman steps combined per extrapolation (k in Rosman et al.), ≥ 1
  Eigen::VectorXd vertex_weights;  // n positive weights wᵢ (wᵢⱼ = wᵢwⱼ); empty: uniform
  ProgressFn progress;             // stage "smacof": (iterations done, max_iterations)

  // Every field by name, for cache keys (support/option_fields.h). Self: SmacofOptions, const or not.
  template <class Self, class Visit>
  static void for_each_field(Self& o, Visit&& visit) {
    visit("max_iterations", o.max_iterations);
    visit("tolerance", o.tolerance);
    visit("target_stress", o.target_stress);
    visit("acceleration", o.acceleration);
    visit("extrapolation_window", o.extrapolation_window);
    visit("vertex_weights", o.vertex_weights);  // by value: other weights of the same count, another form
    visit("progress", o.progress, kNoEffect);   // reports, computes nothing
  }
};

struct SmacofResult {
  Points X;                      // n×3, weighted-centred (Σ wᵢ xᵢ = 0), units of D
  double stress = 0;             // σ(X), unnormalised
  double normalized_stress = 0;  // σ(X) / Σ_{i<j} wᵢⱼ δᵢⱼ²
  // One entry per accepted configuration, starting with the initial one: its normalised stress, the number
  // of passes over D spent when it was evaluated, and whether it came from an extrapolation. Non-increasing.
  std::vector<double> stress_history;
  std::vector<int> passes_history;
  std::vector<bool> extrapolated_history;
  int iterations = 0;  // passes over D after the initial one
  int extrapolations_accepted = 0;
  int extrapolations_rejected = 0;
  std::string stop_reason;           // "converged", "target stress", "max iterations"
  double seconds = 0;                // wall time of the iterations (validation pass included)
  double seconds_per_iteration = 0;  // seconds / passes, validation excluded
  // CPU seconds of the process (all threads) per pass: on a shared machine, the part of the cost that does
  // not depend on how much CPU the other processes leave us.
  double cpu_seconds_per_iteration = 0;
};

// SMACOF from the initial configuration X0 (n×3: classical MDS, the mesh itself, ...).
SmacofResult smacof(const DistanceMatrix& D, const Points& X0, const SmacofOptions& options = {});

// SMACOF initialised by classical MDS (canon/classical_mds.h) of D.
SmacofResult smacof(const DistanceMatrix& D, const SmacofOptions& options = {});

// One evaluation of the pass: σ(X) and the Guttman transform X⁺ (both as defined above). For tests and
// benchmarks; `weights` empty means uniform.
struct GuttmanTransform {
  double stress = 0;
  Points X_next;
};
GuttmanTransform guttman_transform(const DistanceMatrix& D, const Points& X,
                                   const Eigen::VectorXd& weights = {});

// Checks D for SMACOF: square, n ≥ 4, entries above the diagonal finite and ≥ 0, symmetric to float
// rounding. Throws naming the first offending pair. One pass over D.
void validate_distance_matrix(const DistanceMatrix& D, const std::string& what);

// Per-vertex weights proportional to vertex areas (a third of the incident triangles' areas), mean 1:
// the weights that make σ a discretisation of the stress integral over the surface.
Eigen::VectorXd vertex_area_weights(const Mesh& mesh);

}  // namespace cshapes
