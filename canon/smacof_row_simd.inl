// The vector part of SMACOF's row pass (canon/smacof.cpp), written once over the vector type V of
// support/simd_vector.inl and included inside one namespace per instruction set, under that set's
// `#pragma GCC target` (no headers here: the includer provides them).

// Row i against columns [j, j + k·kLanes) ⊆ [j, jb) of the tile starting at column j0, whole vectors only:
// adds into sums[0..3] (x, y, z, stress) and into col_{x,y,z}[j − j0] as row_pass does, and returns the first
// column left for the scalar remainder. 1/d is the hardware estimate with one Newton step (about 23 bits), 0
// for coincident points.
// `ahead` is the entries of a later row (indexed like `delta`) to prefetch along the way, one cache line
// per two vectors.
template <bool Weighted>
inline Index row_vector_part(const float* delta, const float* ahead, const float* xs, const float* ys,
                             const float* zs, const float* ws, float xi, float yi, float zi, float wi, Index j,
                             Index jb, Index j0, float* col_x, float* col_y, float* col_z, double* sums) {
  using F = typename V::F;
  const F vxi = V::set1(xi), vyi = V::set1(yi), vzi = V::set1(zi), vwi = V::set1(wi);
  const F half = V::set1(0.5f), three_halves = V::set1(1.5f), tiny = V::set1(FLT_MIN);
  F ax = V::zero(), ay = V::zero(), az = V::zero(), as = V::zero();
  auto step = [&](Index j) {
    const F dlt = V::loadu(delta + j);
    const F dx = V::sub(vxi, V::loadu(xs + j));
    const F dy = V::sub(vyi, V::loadu(ys + j));
    const F dz = V::sub(vzi, V::loadu(zs + j));
    const F d2 = V::fmadd(dx, dx, V::fmadd(dy, dy, V::mul(dz, dz)));
    const F r0 = V::rsqrt(d2);
    const F h = V::mul(V::mul(half, d2), V::mul(r0, r0));
    const F inv = V::keep_where(V::gt(d2, tiny), V::mul(r0, V::sub(three_halves, h)));
    const F residual = V::sub(dlt, V::mul(d2, inv));
    const F ratio = V::mul(dlt, inv);
    F row_coef = ratio, col_coef = ratio;
    if constexpr (Weighted) {
      const F wj = V::loadu(ws + j);
      row_coef = V::mul(ratio, wj);
      col_coef = V::mul(ratio, vwi);
      as = V::fmadd(V::mul(wj, residual), residual, as);
    } else {
      as = V::fmadd(residual, residual, as);
    }
    ax = V::fmadd(row_coef, dx, ax);
    ay = V::fmadd(row_coef, dy, ay);
    az = V::fmadd(row_coef, dz, az);
    float* px = col_x + (j - j0);
    float* py = col_y + (j - j0);
    float* pz = col_z + (j - j0);
    V::storeu(px, V::fnmadd(col_coef, dx, V::loadu(px)));
    V::storeu(py, V::fnmadd(col_coef, dy, V::loadu(py)));
    V::storeu(pz, V::fnmadd(col_coef, dz, V::loadu(pz)));
  };
  static_assert(2 * V::kLanes * sizeof(float) == 64, "one cache line per two vectors");
  for (; j + 2 * V::kLanes <= jb; j += 2 * V::kLanes) {
    __builtin_prefetch(ahead + j, 0, 3);
    step(j);
    step(j + V::kLanes);
  }
  for (; j + V::kLanes <= jb; j += V::kLanes) step(j);
  alignas(V::kAlign) float lanes[4][V::kLanes];
  V::store(lanes[0], ax), V::store(lanes[1], ay), V::store(lanes[2], az), V::store(lanes[3], as);
  for (int k = 0; k < V::kLanes; ++k)
    for (int c = 0; c < 4; ++c) sums[c] += static_cast<double>(lanes[c][k]);
  return j;
}
