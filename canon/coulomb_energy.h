// The Coulomb energy of eq. (1) and its gradient.
//
//   E(X) = Σ_{i≠j} 1 / ‖x_i − x_j‖          (ordered pairs, as the paper writes it: each pair counted twice)
//   ∇_i E = −2 Σ_{j≠i} (x_i − x_j) / ‖x_i − x_j‖³
//
// Distances below `min_distance` are raised to it, so coincident points give finite values (their mutual
// force is then zero, as x_i − x_j = 0).
#pragma once

#include "core/types.h"

namespace cshapes {

struct CoulombOptions {
  enum class Summation {
    Auto,    // direct below a measured size, fast above
    Direct,  // exact O(n²) summation: the reference
    Fast     // hierarchical O(n log n) summation with the accuracy below
  };
  Summation summation = Summation::Auto;
  double accuracy = 1e-3;   // fast summation: target relative L2 error of the gradient vs direct summation
  double min_distance = 0;  // distance floor; 0 means 1e-9 × the bounding-box diagonal of X
};

struct CoulombEvaluation {
  double energy = 0;
  Points gradient;  // n×3, ∇E
};

// Energy and gradient by the summation the options pick.
CoulombEvaluation coulomb_energy_gradient(const Points& X, const CoulombOptions& options = {});

// Exact direct summation in double precision, OpenMP over targets. O(n²). The reference for everything else.
CoulombEvaluation coulomb_direct(const Points& X, double min_distance = 0);

// The floor actually used for X when options.min_distance is 0.
double default_min_distance(const Points& X);

}  // namespace cshapes
