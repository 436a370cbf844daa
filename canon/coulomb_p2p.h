// Internal to canon/coulomb_energy.cpp and canon/coulomb_fmm.cpp: the float particle-to-particle kernels,
// compiled for each instruction set of support/simd.h and dispatched at run time (canon/coulomb_p2p.cpp; the
// vector versions in canon/coulomb_p2p_simd.inl).
//
// For up to kBlock consecutive targets i0 … i0+count−1 and a list of source index ranges (all indices into
// the same float structure-of-arrays x, y, z) it adds, per target i,
//   potential[i] += Σ_j 1/r_ij,   force[i] += Σ_j (x_i − x_j)/r_ij³,   r_ij = max(‖x_i − x_j‖, floor)
// skipping j = i. Pair terms are float (AVX2 and AVX-512: the hardware reciprocal square root estimate + one
// Newton step, relative error ≈ 1e-7; baseline: 1/sqrt), kept in registers, and flushed into the double
// accumulators at least every kFlushEvery sources, so float round-off never builds up over long sums. The
// loop is over sources with the targets in the vector lanes: no horizontal reductions. Deterministic: the
// order of every addition is fixed by the inputs.
//
// Coordinates are split into float high and low parts (x = hi + lo, |lo| ≤ ulp(hi)/2) and differences are
// formed as (hi_i − hi_j) + (lo_i − lo_j): the first subtraction is exact for close points (Sterbenz), so the
// difference of two close points keeps ~1e-7 relative accuracy instead of 1e-7 of the box size. Without it a
// pair of random points 1e-3 apart in a unit box gets a 1e-4 relative force error, which dominates the
// gradient error of the points involved.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <type_traits>

#include "cshapes/support/types.h"

namespace cshapes::coulomb_detail {

struct SourceRange {
  int32_t begin, end;  // [begin, end) indices into the coordinate arrays
};

constexpr int kBlock = 16;  // at most this many targets per call (the kernels split it into vector blocks)
constexpr int kFlushEvery = 512;  // sources summed in float before flushing into double

// Coordinates mapped to the cube [-1, 1]³ (x' = (x − center)/scale), so float arithmetic never over- or
// underflows whatever the input's units; results are scaled back (potential /scale, gradient /scale²).
struct NormalizedPoints {
  Eigen::RowVector3d center = Eigen::RowVector3d::Zero();
  double scale = 1;  // half the largest bounding-box extent (1 for a single point)
  float floor2 = 0;  // squared distance floor in normalized units
};
NormalizedPoints normalize_points(const Points& X, double min_distance);  // min_distance 0: the default

struct FloatPoints {
  const float *x, *y, *z;           // high parts: float(x)
  const float *x_lo, *y_lo, *z_lo;  // low parts: float(x − float(x))
};

// Splits normalized double coordinates into the high and low float arrays of FloatPoints.
inline void split_float(double value, float& hi, float& lo) {
  hi = static_cast<float>(value);
  lo = static_cast<float>(value - static_cast<double>(hi));
}

// Adds the sums over the sources `ranges` into potential[i], fx[i], fy[i], fz[i] for the targets
// i0 … i0+count−1 (count ≤ kBlock) of the structure-of-arrays p. Dispatched by simd_target().
void p2p_block(const FloatPoints& p, Index i0, int count, const SourceRange* ranges, int num_ranges,
               float floor2, double* potential, double* fx, double* fy, double* fz);

// The FMM's near field, in local frames. Each source leaf keeps its points as floats relative to a frame
// origin near it (its parent cell's centre), and a block of kBlock targets is converted to that frame (in
// double, then rounded) once per source range, so a float difference carries ~1e-7 of the frame's size S
// instead of the bounding box's: the high/low split of FloatPoints is not needed, which saves 6 of the 24
// vector operations per pair. A pair closer than S/256 (where that rounding would exceed ~1e-5 of the
// distance: near-duplicate points) is left out of the float sum and summed exactly in double instead, so
// near-coincident points cost accuracy nowhere.
// Coordinates are stored scaled by 1/√2 (kFrameScale): with h = ‖d'‖² = r²/2 and y ≈ rsqrt(h), one Newton
// step is w = y (3 − h y²) = 2√2/r (to ~23 bits), so 1/r = w/(2√2) and d/r³ = d' w³/16: the constants are
// applied once per flush. refine = false skips the step (w = y = √2/r to the estimate's 12 bits, for the
// FMM's looser accuracies: kUnrefinedMinAccuracy in coulomb_fmm_expansions.cpp).
// Same semantics as p2p_block otherwise: skips j = i, distance floor, float terms flushed into double at
// least every kFlushEvery sources, every addition in an order fixed by the inputs.
constexpr double kFrameScale = 0.70710678118654752440;
constexpr double kCloseFraction =
    1.0 / 256;  // pairs closer than this × the frame's size are summed in double

// Frame coordinate of a point: float((x − origin)·kFrameScale). The one rounding rule for targets and
// sources.
inline float frame_coordinate(double x, double origin) {
  return static_cast<float>((x - origin) * kFrameScale);
}

// Source points [begin, end) of the frame-coordinate arrays, in the frame with origin `origin` (normalized
// coordinates); close_h: pairs with h = ‖d'‖² below it are summed exactly (frame_close_h).
struct FramedRange {
  double origin[3];
  int32_t begin, end;
  float close_h;
};

// close_h of a frame of radius `frame_radius` (normalized units): h of a pair at kCloseFraction × radius,
// at least the smallest normal float so that a point and itself always count as close.
inline float frame_close_h(double frame_radius) {
  const double d = kCloseFraction * frame_radius * kFrameScale;
  return std::max(static_cast<float>(d * d), std::numeric_limits<float>::min());
}

// For the targets i0 … i0+count−1 (count ≤ kBlock; normalized double coordinates x, y, z, which are also the
// sources' exact coordinates) and the source ranges `ranges` (frame coordinates sx, sy, sz), adds the sums
// into potential[i], fx[i], fy[i], fz[i]. self_range: the index of the range that contains the targets
// themselves (source i0 + l is target lane l), or −1. floor2: squared distance floor (normalized units).
// Dispatched by simd_target().
void p2p_framed_block(const double* x, const double* y, const double* z, Index i0, int count,
                      const FramedRange* ranges, int num_ranges, int self_range, const float* sx,
                      const float* sy, const float* sz, float floor2, bool refine, double* potential,
                      double* fx, double* fy, double* fz);

}  // namespace cshapes::coulomb_detail
