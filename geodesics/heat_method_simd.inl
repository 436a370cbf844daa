// The divergence step of geodesics/heat_method.cpp (HeatMethod::Impl::divergence), compiled per instruction set:
// included there inside one namespace per set (under that set's `#pragma GCC target` and fp-contract=off, or
// none for the baseline). No headers here. Every loop is element-wise over the k sources (the one
// reduction is an OR), and no multiply-add is fused, so every set computes the same bytes.

// b += Σ_f Σ_c (r_c · X_f) e_{v_c}, X_f = -∇u / |∇u| per source, over faces [0, m): F0, F1, F2 the faces'
// corners, g and rho as HeatMethod::Impl's, u and b n × k row-major, x and y k doubles of work space.
void divergence_faces(long m, const int* F0, const int* F1, const int* F2, const double* g, const double* rho,
                      const double* u, double* b, long k, double* __restrict x, double* __restrict y) {
  for (long f = 0; f < m; ++f) {
    const double* gf = &g[6 * f];
    const double rho_f = rho[f];
    const int corners[3] = {F0[f], F1[f], F2[f]};
    const double* __restrict u0 = u + static_cast<long>(corners[0]) * k;
    const double* __restrict u1 = u + static_cast<long>(corners[1]) * k;
    const double* __restrict u2 = u + static_cast<long>(corners[2]) * k;
    int tiny = 0;
#pragma omp simd reduction(| : tiny)
    for (long c = 0; c < k; ++c) {
      const double ax = u0[c] * gf[0] + u1[c] * gf[2] + u2[c] * gf[4];
      const double ay = u0[c] * gf[1] + u1[c] * gf[3] + u2[c] * gf[5];
      const double norm2 = ax * ax + ay * ay;  // ≤ 9e300 since u ≤ kHeatPeak and |g| ≤ 1
      // Where u underflowed, or is constant, there is no direction to follow: X = 0.
      const bool trusted = std::min(std::min(u0[c], u1[c]), u2[c]) >= kHeatFloor;
      const double scale = trusted && norm2 > 0 ? -rho_f / std::sqrt(norm2) : 0.0;
      x[c] = ax * scale;
      y[c] = ay * scale;
      tiny |= trusted & (norm2 < kTinySquare);
    }
    if (tiny) {  // far from the source: |∇u|² lost precision to subnormals; normalise a / max|a_i| instead
      for (long c = 0; c < k; ++c) {
        const double ax = u0[c] * gf[0] + u1[c] * gf[2] + u2[c] * gf[4];
        const double ay = u0[c] * gf[1] + u1[c] * gf[3] + u2[c] * gf[5];
        const double big = std::max(std::abs(ax), std::abs(ay));
        const bool trusted = std::min(std::min(u0[c], u1[c]), u2[c]) >= kHeatFloor;
        if (!trusted || !(ax * ax + ay * ay < kTinySquare) || big == 0) continue;
        const double sx = ax / big, sy = ay / big, scale = -rho_f / std::sqrt(sx * sx + sy * sy);
        x[c] = sx * scale;
        y[c] = sy * scale;
      }
    }
    for (int corner = 0; corner < 3; ++corner) {
      double* __restrict bv = b + static_cast<long>(corners[corner]) * k;
      const double gx_c = gf[2 * corner], gy_c = gf[2 * corner + 1];
#pragma omp simd
      for (long c = 0; c < k; ++c) bv[c] += gx_c * x[c] + gy_c * y[c];
    }
  }
}
