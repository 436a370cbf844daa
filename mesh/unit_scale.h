// The power of two that brings a point set to unit size, for algorithms whose arithmetic or tolerances
// assume coordinates of order one (CGAL's remeshing, AABB trees, eigen solvers with absolute thresholds).
//
// Multiplying doubles by a power of two is exact (no rounding, barring overflow and subnormals), so an
// algorithm run on the scaled points and scaled back gives the same bits as on the original points whenever
// the algorithm itself is scale-equivariant, and works at any finite scale (1e-100 … 1e100) where it
// otherwise underflows or overflows: lengths to the 4th power leave the double range beyond about 1e±77.
#pragma once

#include <Eigen/Core>

#include "cshapes/support/types.h"

namespace cshapes {

// The power of two f such that f × the largest extent of the axis-aligned bounding box of the finite rows
// of V lies in [0.5, 1). 1 when there is no finite row or the extent is 0 (nothing to scale).
double power_of_two_unit_scale(const Eigen::Ref<const Points>& V);

}  // namespace cshapes
