// The vector particle-to-particle kernels of canon/coulomb_p2p.h, written once over the vector type V of
// support/simd_vector.inl and included by canon/coulomb_p2p.cpp inside one namespace per instruction set, under
// that set's `#pragma GCC target` (no headers here: the includer provides them).
// Each target lane's sums depend only on the sources and their order, never on the other lanes of its
// block, so blocks of 4 (SSE2), 8 (AVX2) and 16 (AVX-512) lanes give each target the same operations; and
// every operation is one IEEE rounding the three sets share (no fused multiply-add; the includer compiles
// with -ffp-contract=off so that the compiler fuses none either) or the same `rsqrtps` estimate. So every
// target gives the same bytes on one processor.

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
      F r2 = V::add(V::mul(ddx, ddx), V::add(V::mul(ddy, ddy), V::mul(ddz, ddz)));
      r2 = V::max(r2, vfloor2);
      F inv_r = V::rsqrt(r2);
      // One Newton step: y ← y (3/2 − r² y²/2), to about 23 correct bits.
      inv_r = V::mul(inv_r, V::sub(three_halves, V::mul(V::mul(half, r2), V::mul(inv_r, inv_r))));
      if constexpr (kSelf) inv_r = V::zero_where(V::lane_is(lane_index, j), inv_r);
      const F inv_r3 = V::mul(inv_r, V::mul(inv_r, inv_r));
      acc[0] = V::add(acc[0], inv_r);
      acc[1] = V::add(acc[1], V::mul(ddx, inv_r3));
      acc[2] = V::add(acc[2], V::mul(ddy, inv_r3));
      acc[3] = V::add(acc[3], V::mul(ddz, inv_r3));
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

// One vector block (count ≤ V::kLanes targets) of p2p_framed_block, in its phases: per source range, a pass
// over the sources (optimistic for ranges that fit one flush, masked otherwise) and the close pairs exactly;
// then the sums written out. Refine: the estimate y ≈ 1/√h refined by one Newton step, w = y (3 − h y²)
// = 2√2/r (about 23 bits), or w = y = √2/r as the hardware gives it (12 bits; see coulomb_p2p.h).
template <bool Refine>
class FramedBlock {
 public:
  using F = typename V::F;
  using M = typename V::M;
  static constexpr int L = V::kLanes;

  FramedBlock(const double* x, const double* y, const double* z, Index i0, int count, const float* sx,
              const float* sy, const float* sz, float floor2)
      : x_(x), y_(y), z_(z), sx_(sx), sy_(sy), sz_(sz), i0_(i0), count_(count), floor2_(floor2),
        floor_(V::set1(0.5f * floor2)), three_(V::set1(3.0f)), lanes_(V::iota(static_cast<int32_t>(i0))) {
    for (int l = 0; l < L; ++l) {  // pad a short block with its last target; padded lanes are dropped
      const Index i = i0 + (l < count ? l : count - 1);
      target_[0][l] = x[i], target_[1][l] = y[i], target_[2][l] = z[i];
    }
  }

  // The sources of one range, in its frame; self: the range holds the targets themselves.
  void add_range(const FramedRange& range, bool self) {
    alignas(V::kAlign) float t[3][L];
    const F tx = V::to_frame(target_[0], range.origin[0], kFrameScale),
            ty = V::to_frame(target_[1], range.origin[1], kFrameScale),
            tz = V::to_frame(target_[2], range.origin[2], kFrameScale);
    bool any_close = false;
    const int32_t size = range.end - range.begin;
    if (!self && size <= kFlushEvery) {  // one pass, optimistic first
      if (pending_ + size > kFlushEvery) flush(), pending_ = 0;
      const F saved[4] = {ap_, ax_, ay_, az_};
      if (sum_sources_optimistic(tx, ty, tz, range.begin, range.end, range.close_h)) {
        ap_ = saved[0], ax_ = saved[1], ay_ = saved[2], az_ = saved[3];
        sum_sources(tx, ty, tz, range.begin, range.end, range.close_h, std::false_type{});
        V::store(t[0], tx), V::store(t[1], ty), V::store(t[2], tz);
        sum_close_pairs(t, range.begin, range.end, range.close_h);
      }
      pending_ += size;
      return;
    }
    for (int32_t begin = range.begin; begin < range.end;) {
      const int32_t end = std::min<int32_t>(range.end, begin + (kFlushEvery - pending_));
      if (self)
        any_close |= sum_sources(tx, ty, tz, begin, end, range.close_h, std::true_type{});
      else
        any_close |= sum_sources(tx, ty, tz, begin, end, range.close_h, std::false_type{});
      pending_ += end - begin;
      begin = end;
      if (pending_ == kFlushEvery) flush(), pending_ = 0;
    }
    if (any_close) {
      V::store(t[0], tx), V::store(t[1], ty), V::store(t[2], tz);
      sum_close_pairs(t, range.begin, range.end, range.close_h);
    }
  }

  // The float accumulators into the double sums, then the block's sums (times the frame's constants) and
  // the exact close terms added to the outputs.
  void finish(double* potential, double* fx, double* fy, double* fz) {
    // 1/r = w/(2√2) and d/r³ = d' w³/16 with the Newton step; 1/r = w/√2 and d/r³ = d' w³/2 without.
    constexpr double kPotentialScale = Refine ? 0.35355339059327376220 : 0.70710678118654752440;
    constexpr double kForceScale = Refine ? 1.0 / 16 : 1.0 / 2;
    flush();
    for (int l = 0; l < count_; ++l) {
      potential[i0_ + l] += sum_[0][l] * kPotentialScale + exact_[0][l];
      fx[i0_ + l] += sum_[1][l] * kForceScale + exact_[1][l];
      fy[i0_ + l] += sum_[2][l] * kForceScale + exact_[2][l];
      fz[i0_ + l] += sum_[3][l] * kForceScale + exact_[3][l];
    }
  }

 private:
  void flush() {
    alignas(V::kAlign) float a[4][L];
    V::store(a[0], ap_), V::store(a[1], ax_), V::store(a[2], ay_), V::store(a[3], az_);
    ap_ = ax_ = ay_ = az_ = V::zero();
    for (int k = 0; k < 4; ++k)
      for (int l = 0; l < L; ++l) sum_[k][l] += static_cast<double>(a[k][l]);
  }

  // The close pairs of targets t (frame coordinates) and sources [begin, end): the same float h as the
  // vector loop (the same IEEE operations), then the exact term in double.
  void sum_close_pairs(const float (&t)[3][L], int32_t begin, int32_t end, float close_h) {
    for (int l = 0; l < count_; ++l)
      for (int32_t j = begin; j < end; ++j) {
        const float dx = t[0][l] - sx_[j], dy = t[1][l] - sy_[j], dz = t[2][l] - sz_[j];
        const float h = dx * dx + (dy * dy + dz * dz);
        if (!(h < close_h) || j == i0_ + l) continue;
        const double ex = target_[0][l] - x_[j], ey = target_[1][l] - y_[j], ez = target_[2][l] - z_[j];
        const double r2 = std::max(ex * ex + ey * ey + ez * ez, static_cast<double>(floor2_));
        const double inv_r = 1 / std::sqrt(r2), inv_r3 = inv_r / r2;
        exact_[0][l] += inv_r, exact_[1][l] += ex * inv_r3, exact_[2][l] += ey * inv_r3,
            exact_[3][l] += ez * inv_r3;
      }
  }

  // The common case, optimistic: sums every pair and only tracks the smallest h (1 operation per pair instead
  // of 3); returns whether some pair was close, in which case the caller discards this pass. Both loops
  // accumulate in locals and store the members once at the end.
  bool sum_sources_optimistic(F tx, F ty, F tz, int32_t begin, int32_t end, float close_h) {
    F smallest = V::set1(std::numeric_limits<float>::max());
    F ap = ap_, ax = ax_, ay = ay_, az = az_;
    for (int32_t j = begin; j < end; ++j) {
      const F dx = V::sub(tx, V::broadcast(sx_ + j));
      const F dy = V::sub(ty, V::broadcast(sy_ + j));
      const F dz = V::sub(tz, V::broadcast(sz_ + j));
      const F h0 = V::add(V::mul(dx, dx), V::add(V::mul(dy, dy), V::mul(dz, dz)));
      smallest = V::min(smallest, h0);
      const F h = V::max(h0, floor_);
      const F r = V::rsqrt(h);
      const F w = Refine ? V::mul(r, V::sub(three_, V::mul(h, V::mul(r, r)))) : r;
      const F w3 = V::mul(w, V::mul(w, w));
      ap = V::add(ap, w);
      ax = V::add(ax, V::mul(dx, w3));
      ay = V::add(ay, V::mul(dy, w3));
      az = V::add(az, V::mul(dz, w3));
    }
    ap_ = ap, ax_ = ax, ay_ = ay, az_ = az;
    return V::any(V::lt(smallest, V::set1(close_h)));
  }

  // Leaves close pairs (and i = j) out; returns whether some pair other than i = j was close to a target of
  // the block (a padded lane repeats the last target, so it is close to that target's own source: no reason
  // to look for close pairs).
  template <class SelfTag>
  bool sum_sources(F tx, F ty, F tz, int32_t begin, int32_t end, float close_h, SelfTag) {
    constexpr bool kSelf = SelfTag::value;
    const F close_limit = V::set1(close_h);
    M any_close = V::no_lanes();
    F ap = ap_, ax = ax_, ay = ay_, az = az_;
    for (int32_t j = begin; j < end; ++j) {
      const F dx = V::sub(tx, V::broadcast(sx_ + j));
      const F dy = V::sub(ty, V::broadcast(sy_ + j));
      const F dz = V::sub(tz, V::broadcast(sz_ + j));
      const F h0 = V::add(V::mul(dx, dx), V::add(V::mul(dy, dy), V::mul(dz, dz)));
      M close = V::lt(h0, close_limit);
      const F h = V::max(h0, floor_);
      const F r = V::rsqrt(h);
      const F w = V::zero_where(close, Refine ? V::mul(r, V::sub(three_, V::mul(h, V::mul(r, r)))) : r);
      if constexpr (kSelf)  // i = j is close too, but needs no exact term
        close = V::mask_and_not(V::lane_is(lanes_, j), close);
      any_close = V::mask_or(any_close, close);
      const F w3 = V::mul(w, V::mul(w, w));
      ap = V::add(ap, w);
      ax = V::add(ax, V::mul(dx, w3));
      ay = V::add(ay, V::mul(dy, w3));
      az = V::add(az, V::mul(dz, w3));
    }
    ap_ = ap, ax_ = ax, ay_ = ay, az_ = az;
    return V::any_first(any_close, count_);
  }

  const double *x_, *y_, *z_;
  const float *sx_, *sy_, *sz_;
  const Index i0_;
  const int count_;
  const float floor2_;
  const F floor_, three_;
  const typename V::I lanes_;
  alignas(V::kAlign) double target_[3][L];
  double sum_[4][L] = {};    // potential and force sums before the frame's constants, per lane
  double exact_[4][L] = {};  // the close pairs' exact potential and force sums, per lane
  int pending_ = 0;          // pairs in the float accumulators since the last flush
  F ap_ = V::zero(), ax_ = V::zero(), ay_ = V::zero(), az_ = V::zero();
};

template <bool Refine>
inline void p2p_framed_vector_block(const double* x, const double* y, const double* z, Index i0, int count,
                                    const FramedRange* ranges, int num_ranges, int self_range,
                                    const float* sx, const float* sy, const float* sz, float floor2,
                                    double* potential, double* fx, double* fy, double* fz) {
  FramedBlock<Refine> block(x, y, z, i0, count, sx, sy, sz, floor2);
  for (int r = 0; r < num_ranges; ++r) block.add_range(ranges[r], r == self_range);
  block.finish(potential, fx, fy, fz);
}

inline void p2p_framed_block(const double* x, const double* y, const double* z, Index i0, int count,
                             const FramedRange* ranges, int num_ranges, int self_range, const float* sx,
                             const float* sy, const float* sz, float floor2, bool refine, double* potential,
                             double* fx, double* fy, double* fz) {
  for (int first = 0; first < count; first += V::kLanes) {
    const int lanes = std::min(V::kLanes, count - first);
    if (refine)
      p2p_framed_vector_block<true>(x, y, z, i0 + first, lanes, ranges, num_ranges, self_range, sx, sy, sz,
                                    floor2, potential, fx, fy, fz);
    else
      p2p_framed_vector_block<false>(x, y, z, i0 + first, lanes, ranges, num_ranges, self_range, sx, sy, sz,
                                     floor2, potential, fx, fy, fz);
  }
}
