#include "cshapes/mesh/unit_scale.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace cshapes {

double power_of_two_unit_scale(const Eigen::Ref<const Points>& V) {
  double half_extent = 0;
  for (int axis = 0; axis < 3; ++axis) {
    double lo = std::numeric_limits<double>::infinity(), hi = -lo;
    for (Index i = 0; i < V.rows(); ++i) {
      const double x = V(i, axis);
      if (!std::isfinite(V(i, 0)) || !std::isfinite(V(i, 1)) || !std::isfinite(V(i, 2))) continue;
      lo = std::min(lo, x);
      hi = std::max(hi, x);
    }
    // Halves first: hi - lo overflows for coordinates near the largest double.
    if (hi >= lo) half_extent = std::max(half_extent, 0.5 * hi - 0.5 * lo);
  }
  if (!(half_extent > 0) || !std::isfinite(half_extent)) return 1;
  int exponent = 0;
  std::frexp(half_extent, &exponent);  // half_extent = m · 2^exponent, m in [0.5, 1)
  // 2 · half_extent · 2^-(exponent + 1) = m in [0.5, 1); subnormal extents get the largest finite factor.
  return std::ldexp(1.0, std::min(-(exponent + 1), std::numeric_limits<double>::max_exponent - 1));
}

}  // namespace cshapes
