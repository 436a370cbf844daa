// The vector particle-to-particle kernels of canon/coulomb_p2p.h, written once over the vector type V of
// core/simd_vector.inl and included by canon/coulomb_p2p.cpp inside one namespace per instruction set, under
// that set's `#pragma GCC target` (no headers here: the includer provides them).
// Each target lane's sums depend only on the sources and their order, never on the other lanes of its
// block, so blocks of 8 (AVX2) and 16 (AVX-512) lanes give each target the same operations.

// One vector block (count ≤ V::kLanes) of p2p_block.
inline void p2p_vector_block(const FloatPoints& p, Index i0, int count, const SourceRange* ranges,
                             int num_ranges, float floor2, double* potential, double* fx, double* fy,
                             double* fz) {
  using F = typename V::F;
  constexpr int L = V::kLanes;
  alignas(V::kAlign) float t[6][L];
  for (int l = 0; l < L; ++l) {  // pad a short block with its last target; padded lanes are dropped
    const Index i = i0 + (l < count ? l : count - 1);
    t[0][l] = p.x[i], t[1][l] = p.y[i], t[2][l] = p.z[i];
    t[3][l] = p.x_lo[i], t[4][l] = p.y_lo[i], t[5][l] = p.z_lo[i];
  }
  const F vx = V::load(t[0]), vy = V::load(t[1]), vz = V::load(t[2]);
  const F vx_lo = V::load(t[3]), vy_lo = V::load(t[4]), vz_lo = V::load(t[5]);
  const typename V::I lane_index = V::iota(static_cast<int32_t>(i0));
  const F vfloor2 = V::set1(floor2), half = V::set1(0.5f), three_halves = V::set1(1.5f);
  double sum[4][L] = {};                                    // [potential, x, y, z][lane], in double
  F acc[4] = {V::zero(), V::zero(), V::zero(), V::zero()};  // float partial sums, flushed into sum
  auto flush = [&]() {
    alignas(V::kAlign) float a[4][L];
    for (int k = 0; k < 4; ++k) V::store(a[k], acc[k]), acc[k] = V::zero();
    for (int k = 0; k < 4; ++k)
      for (int l = 0; l < L; ++l) sum[k][l] += static_cast<double>(a[k][l]);
  };
  // Sources [begin, end) with or without the i = j mask (a compile-time choice, so the common case pays
  // nothing for it).
  auto sum_sources = [&](int32_t begin, int32_t end, auto self_tag) {
    constexpr bool kSelf = decltype(self_tag)::value;
    for (int32_t j = begin; j < end; ++j) {
      const F ddx = V::add(V::sub(vx, V::broadcast(p.x + j)), V::sub(vx_lo, V::broadcast(p.x_lo + j)));
      const F ddy = V::add(V::sub(vy, V::broadcast(p.y + j)), V::sub(vy_lo, V::broadcast(p.y_lo + j)));
      const F ddz = V::add(V::sub(vz, V::broadcast(p.z + j)), V::sub(vz_lo, V::broadcast(p.z_lo + j)));
      F r2 = V::fmadd(ddx, ddx, V::fmadd(ddy, ddy, V::mul(ddz, ddz)));
      r2 = V::max(r2, vfloor2);
      F inv_r = V::rsqrt(r2);
      // One Newton step: y ← y (3/2 − r² y²/2), to about 23 correct bits.
      inv_r = V::mul(inv_r, V::fnmadd(V::mul(half, r2), V::mul(inv_r, inv_r), three_halves));
      if constexpr (kSelf) inv_r = V::zero_where(V::lane_is(lane_index, j), inv_r);
      const F inv_r3 = V::mul(inv_r, V::mul(inv_r, inv_r));
      acc[0] = V::add(acc[0], inv_r);
      acc[1] = V::fmadd(ddx, inv_r3, acc[1]);
      acc[2] = V::fmadd(ddy, inv_r3, acc[2]);
      acc[3] = V::fmadd(ddz, inv_r3, acc[3]);
    }
  };
  int pending = 0;
  for (int r = 0; r < num_ranges; ++r) {
    const bool has_self = ranges[r].begin < i0 + count && i0 < ranges[r].end;
    for (int32_t begin = ranges[r].begin; begin < ranges[r].end;) {
      const int32_t end = std::min<int32_t>(ranges[r].end, begin + (kFlushEvery - pending));
      if (has_self)
        sum_sources(begin, end, std::true_type{});
      else
        sum_sources(begin, end, std::false_type{});
      pending += end - begin;
      begin = end;
      if (pending == kFlushEvery) flush(), pending = 0;
    }
  }
  flush();
  for (int l = 0; l < count; ++l) {
    potential[i0 + l] += sum[0][l];
    fx[i0 + l] += sum[1][l];
    fy[i0 + l] += sum[2][l];
    fz[i0 + l] += sum[3][l];
  }
}

inline void p2p_block(const FloatPoints& p, Index i0, int count, const SourceRange* ranges, int num_ranges,
                      float floor2, double* potential, double* fx, double* fy, double* fz) {
  for (int first = 0; first < count; first += V::kLanes)
    p2p_vector_block(p, i0 + first, std::min(V::kLanes, count - first), ranges, num_ranges, floor2, potential,
                     fx, fy, fz);
}

// One vector block (count ≤ V::kLanes) of p2p_framed_block.
inline void p2p_framed_vector_block(const double* x, const double* y, const double* z, Index i0, int count,
                                    const FramedRange* ranges, int num_ranges, int self_range,
                                    const float* sx, const float* sy, const float* sz, float floor2,
                                    double* potential, double* fx, double* fy, double* fz) {
  using F = typename V::F;
  using M = typename V::M;
  constexpr int L = V::kLanes;
  constexpr double kPotentialScale = 0.35355339059327376220;  // 1/(2√2)
  constexpr double kForceScale = 1.0 / 16;
  const float half_floor2 = 0.5f * floor2;
  alignas(V::kAlign) double target[3][L];
  for (int l = 0; l < L; ++l) {  // pad a short block with its last target; padded lanes are dropped
    const Index i = i0 + (l < count ? l : count - 1);
    target[0][l] = x[i], target[1][l] = y[i], target[2][l] = z[i];
  }
  double sum[4][L] = {};    // potential and force sums before the frame's constants, per lane
  double exact[4][L] = {};  // the close pairs' exact potential and force sums, per lane
  int pending = 0;
  // The close pairs of targets t (frame coordinates) and sources [begin, end): the same float h as the
  // vector loop (the same IEEE operations), then the exact term in double.
  auto sum_close_pairs = [&](const float(&t)[3][L], int32_t begin, int32_t end, float close_h) {
    for (int l = 0; l < count; ++l)
      for (int32_t j = begin; j < end; ++j) {
        const float dx = t[0][l] - sx[j], dy = t[1][l] - sy[j], dz = t[2][l] - sz[j];
        const float h = std::fma(dx, dx, std::fma(dy, dy, dz * dz));
        if (!(h < close_h) || j == i0 + l) continue;
        const double ex = target[0][l] - x[j], ey = target[1][l] - y[j], ez = target[2][l] - z[j];
        const double r2 = std::max(ex * ex + ey * ey + ez * ez, static_cast<double>(floor2));
        const double inv_r = 1 / std::sqrt(r2), inv_r3 = inv_r / r2;
        exact[0][l] += inv_r, exact[1][l] += ex * inv_r3, exact[2][l] += ey * inv_r3,
            exact[3][l] += ez * inv_r3;
      }
  };
  const F floor = V::set1(half_floor2), three = V::set1(3.0f);
  const typename V::I lanes = V::iota(static_cast<int32_t>(i0));
  F ap = V::zero(), ax = ap, ay = ap, az = ap;
  auto flush = [&]() {
    alignas(V::kAlign) float a[4][L];
    V::store(a[0], ap), V::store(a[1], ax), V::store(a[2], ay), V::store(a[3], az);
    ap = ax = ay = az = V::zero();
    for (int k = 0; k < 4; ++k)
      for (int l = 0; l < L; ++l) sum[k][l] += static_cast<double>(a[k][l]);
  };
  // The common case, optimistic: sums every pair and only tracks the smallest h (1 operation per pair instead
  // of 3); returns whether some pair was close, in which case the caller discards this pass.
  auto sum_sources_optimistic = [&](F tx, F ty, F tz, int32_t begin, int32_t end, float close_h) {
    F smallest = V::set1(std::numeric_limits<float>::max());
    for (int32_t j = begin; j < end; ++j) {
      const F dx = V::sub(tx, V::broadcast(sx + j));
      const F dy = V::sub(ty, V::broadcast(sy + j));
      const F dz = V::sub(tz, V::broadcast(sz + j));
      const F h0 = V::fmadd(dx, dx, V::fmadd(dy, dy, V::mul(dz, dz)));
      smallest = V::min(smallest, h0);
      const F h = V::max(h0, floor);
      const F r = V::rsqrt(h);
      const F w = V::mul(r, V::fnmadd(h, V::mul(r, r), three));
      const F w3 = V::mul(w, V::mul(w, w));
      ap = V::add(ap, w);
      ax = V::fmadd(dx, w3, ax);
      ay = V::fmadd(dy, w3, ay);
      az = V::fmadd(dz, w3, az);
    }
    return V::any(V::lt(smallest, V::set1(close_h)));
  };
  // Leaves close pairs (and i = j) out; returns whether some pair other than i = j was close.
  auto sum_sources = [&](F tx, F ty, F tz, int32_t begin, int32_t end, float close_h, auto self_tag) {
    constexpr bool kSelf = decltype(self_tag)::value;
    const F close_limit = V::set1(close_h);
    M any_close = V::no_lanes();
    for (int32_t j = begin; j < end; ++j) {
      const F dx = V::sub(tx, V::broadcast(sx + j));
      const F dy = V::sub(ty, V::broadcast(sy + j));
      const F dz = V::sub(tz, V::broadcast(sz + j));
      const F h0 = V::fmadd(dx, dx, V::fmadd(dy, dy, V::mul(dz, dz)));
      M close = V::lt(h0, close_limit);
      const F h = V::max(h0, floor);
      const F r = V::rsqrt(h);
      const F w = V::zero_where(close, V::mul(r, V::fnmadd(h, V::mul(r, r), three)));
      if constexpr (kSelf)  // i = j is close too, but needs no exact term
        close = V::mask_and_not(V::lane_is(lanes, j), close);
      any_close = V::mask_or(any_close, close);
      const F w3 = V::mul(w, V::mul(w, w));
      ap = V::add(ap, w);
      ax = V::fmadd(dx, w3, ax);
      ay = V::fmadd(dy, w3, ay);
      az = V::fmadd(dz, w3, az);
    }
    return V::any(any_close);
  };
  for (int r = 0; r < num_ranges; ++r) {
    const FramedRange& range = ranges[r];
    alignas(V::kAlign) float t[3][L];
    const F tx = V::to_frame(target[0], range.origin[0], kFrameScale),
            ty = V::to_frame(target[1], range.origin[1], kFrameScale),
            tz = V::to_frame(target[2], range.origin[2], kFrameScale);
    bool any_close = false;
    const int32_t size = range.end - range.begin;
    if (r != self_range && size <= kFlushEvery) {  // one pass, optimistic first
      if (pending + size > kFlushEvery) flush(), pending = 0;
      const F saved[4] = {ap, ax, ay, az};
      if (sum_sources_optimistic(tx, ty, tz, range.begin, range.end, range.close_h)) {
        ap = saved[0], ax = saved[1], ay = saved[2], az = saved[3];
        sum_sources(tx, ty, tz, range.begin, range.end, range.close_h, std::false_type{});
        V::store(t[0], tx), V::store(t[1], ty), V::store(t[2], tz);
        sum_close_pairs(t, range.begin, range.end, range.close_h);
      }
      pending += size;
      continue;
    }
    for (int32_t begin = range.begin; begin < range.end;) {
      const int32_t end = std::min<int32_t>(range.end, begin + (kFlushEvery - pending));
      if (r == self_range)
        any_close |= sum_sources(tx, ty, tz, begin, end, range.close_h, std::true_type{});
      else
        any_close |= sum_sources(tx, ty, tz, begin, end, range.close_h, std::false_type{});
      pending += end - begin;
      begin = end;
      if (pending == kFlushEvery) flush(), pending = 0;
    }
    if (any_close) {
      V::store(t[0], tx), V::store(t[1], ty), V::store(t[2], tz);
      sum_close_pairs(t, range.begin, range.end, range.close_h);
    }
  }
  flush();
  for (int l = 0; l < count; ++l) {
    potential[i0 + l] += sum[0][l] * kPotentialScale + exact[0][l];
    fx[i0 + l] += sum[1][l] * kForceScale + exact[1][l];
    fy[i0 + l] += sum[2][l] * kForceScale + exact[2][l];
    fz[i0 + l] += sum[3][l] * kForceScale + exact[3][l];
  }
}

inline void p2p_framed_block(const double* x, const double* y, const double* z, Index i0, int count,
                             const FramedRange* ranges, int num_ranges, int self_range, const float* sx,
                             const float* sy, const float* sz, float floor2, double* potential, double* fx,
                             double* fy, double* fz) {
  for (int first = 0; first < count; first += V::kLanes)
    p2p_framed_vector_block(x, y, z, i0 + first, std::min(V::kLanes, count - first), ranges, num_ranges,
                            self_range, sx, sy, sz, floor2, potential, fx, fy, fz);
}
