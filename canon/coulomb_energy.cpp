#include "canon/coulomb_energy.h"

#include <algorithm>
#include <cmath>
#include <vector>

#include "canon/coulomb_fmm.h"
#include "canon/coulomb_p2p.h"
#include "core/error.h"
#include "core/mesh.h"

namespace cshapes {

// Measured crossover (cshapes bench coulomb, uniform cube and tosca5k-surface points, 2 threads, default
// accuracy 1e-3): see the value's comment in the report of the commit that set it.
const Index kAutoFastMinPoints = 4000;

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
  result.potential.resize(n);
  result.summation_used = CoulombOptions::Summation::Direct;
#pragma omp parallel for schedule(dynamic, 64)
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
    result.potential[i] = e;
    result.gradient(i, 0) = -2 * gx;
    result.gradient(i, 1) = -2 * gy;
    result.gradient(i, 2) = -2 * gz;
  }
  // Summed serially in index order so the energy does not depend on the thread count.
  result.energy = result.potential.sum();
  return result;
}

CoulombTargetSums coulomb_direct_targets(const Points& X, const std::vector<Index>& targets, double min_distance) {
  const Index n = X.rows();
  if (min_distance <= 0) min_distance = default_min_distance(X);
  for (Index t : targets) CSHAPES_REQUIRE(t >= 0 && t < n, "coulomb_direct_targets: target index ", t, " outside [0, ", n, ")");
  std::vector<double> x(X.col(0).data(), X.col(0).data() + n), y(X.col(1).data(), X.col(1).data() + n),
      z(X.col(2).data(), X.col(2).data() + n);
  const double floor2 = min_distance * min_distance;
  const Index m = static_cast<Index>(targets.size());
  CoulombTargetSums result;
  result.potential.resize(m);
  result.gradient.resize(m, 3);
#pragma omp parallel for schedule(dynamic, 4)
  for (Index t = 0; t < m; ++t) {
    const Index i = targets[t];
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
    result.potential[t] = e;
    result.gradient(t, 0) = -2 * gx;
    result.gradient(t, 1) = -2 * gy;
    result.gradient(t, 2) = -2 * gz;
  }
  return result;
}

namespace coulomb_detail {

NormalizedPoints normalize_points(const Points& X, double min_distance) {
  const Index n = X.rows();
  NormalizedPoints out;
  if (min_distance <= 0) min_distance = default_min_distance(X);
  Eigen::RowVector3d lo = X.colwise().minCoeff(), hi = X.colwise().maxCoeff();
  if (n == 0) lo.setZero(), hi.setZero();
  out.center = 0.5 * (lo + hi);
  out.scale = 0.5 * (hi - lo).maxCoeff();
  if (!(out.scale > 0)) out.scale = 1;  // a single point, or all coincident
  CSHAPES_REQUIRE(std::isfinite(out.scale), "Coulomb summation: point coordinates must be finite");
  const double floor = min_distance / out.scale;
  // The float paths cannot represent floors below ~1e-19 squared; 1e-15 of the half box is far below any
  // meaningful geometry.
  out.floor2 = static_cast<float>(std::max(floor * floor, 1e-30));
  out.floor2_double = std::max(floor * floor, 1e-30);
  return out;
}

}  // namespace coulomb_detail

CoulombEvaluation coulomb_direct_float(const Points& X, double min_distance, bool want_potentials) {
  using namespace coulomb_detail;
  const Index n = X.rows();
  CSHAPES_REQUIRE(n < (Index(1) << 31) - kBlock, "coulomb_direct_float: too many points (", n, ")");
  const NormalizedPoints norm = normalize_points(X, min_distance);
  std::vector<float> x(n), y(n), z(n);
  for (Index i = 0; i < n; ++i) {
    x[i] = static_cast<float>((X(i, 0) - norm.center[0]) / norm.scale);
    y[i] = static_cast<float>((X(i, 1) - norm.center[1]) / norm.scale);
    z[i] = static_cast<float>((X(i, 2) - norm.center[2]) / norm.scale);
  }
  std::vector<double> potential(n, 0.0), fx(n, 0.0), fy(n, 0.0), fz(n, 0.0);
  const FloatPoints points{x.data(), y.data(), z.data()};
  const Index blocks = (n + kBlock - 1) / kBlock;
#pragma omp parallel for schedule(dynamic, 8)
  for (Index b = 0; b < blocks; ++b) {
    const Index i0 = b * kBlock;
    const int count = static_cast<int>(std::min<Index>(kBlock, n - i0));
    // Only the block's own range needs the i = j mask.
    const SourceRange ranges[3] = {{0, static_cast<int32_t>(i0)},
                                   {static_cast<int32_t>(i0), static_cast<int32_t>(i0 + count)},
                                   {static_cast<int32_t>(i0 + count), static_cast<int32_t>(n)}};
    p2p_block(points, i0, count, ranges, 3, norm.floor2, potential.data(), fx.data(), fy.data(), fz.data());
  }
  CoulombEvaluation result;
  result.summation_used = CoulombOptions::Summation::DirectFloat;
  result.gradient.resize(n, 3);
  const double gradient_scale = -2 / (norm.scale * norm.scale);
  double energy = 0;
  for (Index i = 0; i < n; ++i) {
    energy += potential[i];
    result.gradient(i, 0) = gradient_scale * fx[i];
    result.gradient(i, 1) = gradient_scale * fy[i];
    result.gradient(i, 2) = gradient_scale * fz[i];
  }
  result.energy = energy / norm.scale;
  if (want_potentials) {
    result.potential = Eigen::Map<Eigen::VectorXd>(potential.data(), n) / norm.scale;
  }
  return result;
}

CoulombEvaluation coulomb_energy_gradient(const Points& X, const CoulombOptions& options) {
  using Summation = CoulombOptions::Summation;
  CSHAPES_REQUIRE(X.allFinite(), "Coulomb energy: the ", X.rows(), " points contain a non-finite coordinate");
  Summation summation = options.summation;
  if (summation == Summation::Auto) {
    summation = X.rows() < kAutoFastMinPoints ? Summation::DirectFloat : Summation::Fast;
  }
  switch (summation) {
    case Summation::Direct: {
      CoulombEvaluation result = coulomb_direct(X, options.min_distance);
      if (!options.want_potentials) result.potential.resize(0);
      return result;
    }
    case Summation::DirectFloat:
      return coulomb_direct_float(X, options.min_distance, options.want_potentials);
    case Summation::Fast:
    default: {
      CoulombFmmOptions fmm;
      fmm.accuracy = options.accuracy;
      fmm.min_distance = options.min_distance;
      fmm.want_potentials = options.want_potentials;
      return coulomb_fmm(X, fmm);
    }
  }
}

}  // namespace cshapes
