#include "canon/coulomb_energy.h"

#include <algorithm>
#include <vector>

#include "core/error.h"
#include "core/mesh.h"

namespace cshapes {

double default_min_distance(const Points& X) { return 1e-9 * std::max(bbox_diagonal(X), 1e-300); }

CoulombEvaluation coulomb_direct(const Points& X, double min_distance) {
  const Index n = X.rows();
  if (min_distance <= 0) min_distance = default_min_distance(X);
  // Structure of arrays so the inner loop vectorises.
  std::vector<double> x(X.col(0).data(), X.col(0).data() + n), y(X.col(1).data(), X.col(1).data() + n),
      z(X.col(2).data(), X.col(2).data() + n);
  const double floor2 = min_distance * min_distance;
  CoulombEvaluation result;
  result.gradient.resize(n, 3);
  double energy = 0;
#pragma omp parallel for schedule(dynamic, 64) reduction(+ : energy)
  for (Index i = 0; i < n; ++i) {
    const double xi = x[i], yi = y[i], zi = z[i];
    double gx = 0, gy = 0, gz = 0, e = 0;
#pragma omp simd reduction(+ : gx, gy, gz, e)
    for (Index j = 0; j < n; ++j) {
      const double dx = xi - x[j], dy = yi - y[j], dz = zi - z[j];
      const double r2 = std::max(dx * dx + dy * dy + dz * dz, floor2);
      const double inv_r = (j == i) ? 0.0 : 1.0 / std::sqrt(r2);
      const double inv_r3 = inv_r * inv_r * inv_r;
      e += inv_r;
      gx += dx * inv_r3;
      gy += dy * inv_r3;
      gz += dz * inv_r3;
    }
    energy += e;
    result.gradient(i, 0) = -2 * gx;
    result.gradient(i, 1) = -2 * gy;
    result.gradient(i, 2) = -2 * gz;
  }
  result.energy = energy;
  return result;
}

CoulombEvaluation coulomb_energy_gradient(const Points& X, const CoulombOptions& options) {
  // Fast summation is added beside this file; until then every request is served exactly.
  return coulomb_direct(X, options.min_distance);
}

}  // namespace cshapes
