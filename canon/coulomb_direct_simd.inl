// The exact direct sum of canon/coulomb_energy.cpp, compiled per instruction set: included there inside one
// namespace per set (under that set's `#pragma GCC target`, or none for the baseline). No headers here.

// The exact sums at point i over all j ≠ i (double precision, vectorised over j): the potential e = Σ 1/r_ij
// and g = Σ (x_i − x_j)/r_ij³, with distances floored at sqrt(floor2). Shared by the full and the subset
// direct sums.
void direct_sum_at(Index i, const double* x, const double* y, const double* z, Index n, double floor2,
                   double& e, double& gx, double& gy, double& gz) {
  const double xi = x[i], yi = y[i], zi = z[i];
  double se = 0, sx = 0, sy = 0, sz = 0;
#pragma omp simd reduction(+ : se, sx, sy, sz)
  for (Index j = 0; j < n; ++j) {
    const double dx = xi - x[j], dy = yi - y[j], dz = zi - z[j];
    const double r2 = std::max(dx * dx + dy * dy + dz * dz, floor2);
    const double inv_r = (j == i) ? 0.0 : 1.0 / std::sqrt(r2);
    const double inv_r3 = inv_r * inv_r * inv_r;
    se += inv_r;
    sx += dx * inv_r3;
    sy += dy * inv_r3;
    sz += dz * inv_r3;
  }
  e = se;
  gx = sx;
  gy = sy;
  gz = sz;
}
