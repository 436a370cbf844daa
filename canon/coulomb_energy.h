// The Coulomb energy of eq. (1) and its gradient.
//
//   E(X) = Σ_{i≠j} 1 / ‖x_i − x_j‖          (ordered pairs, as the paper writes it: each pair counted twice)
//   φ_i  = Σ_{j≠i} 1 / ‖x_i − x_j‖          (the potential at x_i, so E = Σ_i φ_i)
//   ∇_i E = 2 ∇φ(x_i) = −2 Σ_{j≠i} (x_i − x_j) / ‖x_i − x_j‖³
//
// Distance floor: distances below `min_distance` are raised to it, so coincident points give finite values:
// two coincident points add 1/min_distance to each other's potential and exert no force on each other
// (x_i − x_j = 0). Points closer than the floor but distinct get the force (x_i − x_j)/min_distance³.
// A given min_distance is raised to at least 1e-12 × the bounding-box diagonal, and the float paths
// (DirectFloat, Fast) raise it to 1e-10 × half the largest extent, so 1/r³ stays finite. When all points
// coincide the diagonal is replaced by max(1, max |coordinate|).
//
// Units: X in the input's length unit L; energy and potentials in 1/L, gradient in 1/L².
// Summations (all deterministic: identical inputs and thread count give bit-identical outputs; in fact the
// result does not depend on the thread count at all):
//   Direct       exact, double precision, OpenMP over targets, O(n²)        — the reference
//   DirectFloat  float pair terms (AVX2 rsqrt + Newton step), double accumulation every ≤ 512 terms;
//                relative error ≈ 1e-6, several times faster than Direct
//   Fast         octree fast multipole method (canon/coulomb_fmm.h), O(n), relative L2 gradient error
//                ≤ `accuracy` (its parameters per accuracy: canon/coulomb_fmm.h)
//   Auto         DirectFloat below 3,000 points (kAutoFastMinPoints), Fast from there on
// (The measurements behind each: docs/coulomb-defaults.md, "The fast sum's parameters".)
#pragma once

#include <string>
#include <vector>

#include "cshapes/support/option_fields.h"
#include "cshapes/support/types.h"

namespace cshapes {

struct CoulombOptions {
  enum class Summation {
    Auto,         // DirectFloat below kAutoFastMinPoints points, Fast from there on
    Direct,       // exact O(n²) summation in double precision: the reference
    DirectFloat,  // O(n²) summation with float pair terms, double accumulation (relative error ~1e-6)
    Fast          // fast multipole method with the accuracy below, O(n)
  };
  Summation summation = Summation::Auto;
  double accuracy = 1e-3;  // fast summation: target relative L2 error of the gradient vs direct summation
                           // (the energy's relative error is then smaller, by far); valid range 1e-2 … 3e-6
  double min_distance = 0;       // distance floor; 0 means 1e-9 × the bounding-box diagonal of X
  bool want_potentials = false;  // also return the per-point potentials φ_i (costs n doubles)

  // Every field by name, for cache keys (support/option_fields.h). Self: CoulombOptions, const or not.
  template <class Self, class Visit>
  static void for_each_field(Self& o, Visit&& visit) {
    visit("summation", o.summation);
    visit("accuracy", o.accuracy);
    visit("min_distance", o.min_distance);
    visit("want_potentials", o.want_potentials);  // an output of its own; may take another summation path
  }
};

// "auto", "direct", "direct-float", "fast" (the CLI's --coulomb-summation); throws listing them otherwise.
CoulombOptions::Summation parse_coulomb_summation(const std::string& name);
std::string to_string(CoulombOptions::Summation summation);

struct CoulombEvaluation {
  double energy = 0;
  Points gradient;  // n×3, ∇E
  Eigen::VectorXd
      potential;  // n, φ_i (empty unless options.want_potentials; always filled by coulomb_direct)
  CoulombOptions::Summation summation_used =
      CoulombOptions::Summation::Direct;  // Direct, DirectFloat or Fast
};

// Below this many points Auto uses DirectFloat, at and above it Fast: the crossover of `cshapes bench
// coulomb` (coulomb_energy.cpp says why 3,000).
extern const Index kAutoFastMinPoints;

class CoulombFmmTree;  // canon/coulomb_fmm.h

// Energy and gradient by the summation the options pick. fmm_tree: the fast summation's tree, kept from one
// call to the next (canon/coulomb_fmm.h), or none; the direct summations do not use it.
CoulombEvaluation coulomb_energy_gradient(const Points& X, const CoulombOptions& options = {},
                                          CoulombFmmTree* fmm_tree = nullptr);

// Exact direct summation in double precision, OpenMP over targets. O(n²). The reference for everything else.
// Fills energy, gradient and potential.
CoulombEvaluation coulomb_direct(const Points& X, double min_distance = 0);

// Direct summation with float pair terms and double accumulation (see DirectFloat above). O(n²).
// Fills energy, gradient and, if want_potentials, potential.
CoulombEvaluation coulomb_direct_float(const Points& X, double min_distance = 0,
                                       bool want_potentials = false);

// Exact double-precision direct sums for a subset of targets (indices into X, any order, repeats allowed),
// against all n sources: potential(t) = φ_{targets[t]}, gradient.row(t) = ∇_{targets[t]} E.
// O(|targets|·n). Used to measure the fast summation's error where a full direct sum is too slow.
struct CoulombTargetSums {
  Eigen::VectorXd potential;  // |targets|
  Points gradient;            // |targets|×3
};
CoulombTargetSums coulomb_direct_targets(const Points& X, const std::vector<Index>& targets,
                                         double min_distance = 0);

// The accuracy of an evaluation against exact direct summation (the reference path every fast summation is
// checked against, in the benchmark and in the tests alike).
struct CoulombErrors {
  double gradient = 0;  // relative L2 error of the gradient, ‖g − g_ref‖ / ‖g_ref‖ (Frobenius, over the rows)
  double energy = 0;  // |E − E_ref| / |E_ref|; on a sample of targets, of Σ_t φ_t instead of E
};
// Against a complete direct sum (coulomb_direct of the same points): all n rows.
CoulombErrors coulomb_errors(const CoulombEvaluation& evaluation, const CoulombEvaluation& reference);
// Against exact sums at a sample of targets (reference = coulomb_direct_targets(X, targets)): the gradient
// error over the targets' rows, the energy error from their potentials, so evaluation.potential is needed
// (want_potentials). O(|targets|).
CoulombErrors coulomb_errors(const CoulombEvaluation& evaluation, const std::vector<Index>& targets,
                             const CoulombTargetSums& reference);
// ‖a − b‖ / ‖b‖ (Frobenius norms; b is the reference).
double relative_l2_error(const Points& a, const Points& b);

// The floor used for X when options.min_distance is 0: 1e-9 × floor_reference_length(X).
double default_min_distance(const Points& X);
// The bounding-box diagonal of X, or max(1, max |coordinate|) when it is 0 (all points coincide).
double floor_reference_length(const Points& X);
// The floor the double-precision paths use for a requested min_distance (0: the default).
double effective_min_distance(const Points& X, double min_distance);

}  // namespace cshapes
