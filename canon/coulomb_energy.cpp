#include "cshapes/canon/coulomb_energy.h"

#include <algorithm>
#include <cmath>
#include <numeric>
#include <vector>

#include "cshapes/canon/coulomb_fmm.h"
#include "cshapes/canon/coulomb_p2p.h"
#include "cshapes/mesh/mesh.h"
#include "cshapes/support/error.h"

namespace cshapes {

// The crossover of `cshapes bench coulomb --points N` (process CPU seconds per gradient, DirectFloat against
// Fast, at the default accuracy): the fast sum wins from fewer points on surfaces than in a volume. Auto
// serves surfaces (meshes, point clouds of surfaces) first and switches between the two crossovers (the
// figures: docs/changelog.md, "The direct/fast crossover of `coulomb_energy_gradient`").
const Index kAutoFastMinPoints = 3000;

double default_min_distance(const Points& X) {
  return 1e-9 * floor_reference_length(X);
}

double floor_reference_length(const Points& X) {
  if (X.rows() == 0) return 1;
  const double diagonal = bbox_diagonal(X);
  if (diagonal > 0) return diagonal;
  return std::max(1.0, X.cwiseAbs().maxCoeff());  // all points coincide
}

double effective_min_distance(const Points& X, double min_distance) {
  const double lowest = 1e-12 * floor_reference_length(X);
  return min_distance > 0 ? std::max(min_distance, lowest) : 1e-9 * floor_reference_length(X);
}

namespace {
// The exact sums at point i over all j ≠ i, in double precision: the potential e = Σ 1/r_ij and
// g = Σ (x_i − x_j)/r_ij³, with distances floored at sqrt(floor2), summed in j order. The reference of the
// fast sums, and of `--coulomb-summation direct`: one scalar loop compiled for the baseline only (no fused
// multiply-adds), so its sums are the same bytes under every target (support/simd.h). A
// vectorised loop would be faster (docs/benchmarks.md, "How the rows are measured") but would sum in an
// order that depends on the vector width.
void direct_sum_at(Index i, const double* x, const double* y, const double* z, Index n, double floor2,
                   double& e, double& gx, double& gy, double& gz) {
  const double xi = x[i], yi = y[i], zi = z[i];
  double se = 0, sx = 0, sy = 0, sz = 0;
  for (Index j = 0; j < n; ++j) {
    if (j == i) continue;
    const double dx = xi - x[j], dy = yi - y[j], dz = zi - z[j];
    const double r2 = std::max(dx * dx + dy * dy + dz * dz, floor2);
    const double inv_r = 1.0 / std::sqrt(r2);
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
}  // namespace

CoulombEvaluation coulomb_direct(const Points& X, double min_distance) {
  const Index n = X.rows();
  min_distance = effective_min_distance(X, min_distance);
  // Structure of arrays: each point's loop streams three arrays.
  std::vector<double> x(X.col(0).data(), X.col(0).data() + n), y(X.col(1).data(), X.col(1).data() + n),
      z(X.col(2).data(), X.col(2).data() + n);
  const double floor2 = min_distance * min_distance;
  CoulombEvaluation result;
  result.gradient.resize(n, 3);
  result.potential.resize(n);
  result.summation_used = CoulombOptions::Summation::Direct;
#pragma omp parallel for schedule(dynamic, 64)
  for (Index i = 0; i < n; ++i) {
    double e, gx, gy, gz;
    direct_sum_at(i, x.data(), y.data(), z.data(), n, floor2, e, gx, gy, gz);
    result.potential[i] = e;
    result.gradient(i, 0) = -2 * gx;
    result.gradient(i, 1) = -2 * gy;
    result.gradient(i, 2) = -2 * gz;
  }
  // Summed serially in index order so the energy does not depend on the thread count.
  result.energy = result.potential.sum();
  return result;
}

CoulombTargetSums coulomb_direct_targets(const Points& X, const std::vector<Index>& targets,
                                         double min_distance) {
  const Index n = X.rows();
  min_distance = effective_min_distance(X, min_distance);
  for (Index t : targets)
    CSHAPES_REQUIRE(t >= 0 && t < n, "coulomb_direct_targets: target index ", t, " outside [0, ", n, ")");
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
    double e, gx, gy, gz;
    direct_sum_at(i, x.data(), y.data(), z.data(), n, floor2, e, gx, gy, gz);
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
  min_distance = effective_min_distance(X, min_distance);
  Eigen::RowVector3d lo = Eigen::RowVector3d::Zero(), hi = lo;
  if (n > 0) lo = X.colwise().minCoeff(), hi = X.colwise().maxCoeff();
  out.center = 0.5 * (lo + hi);
  out.scale = 0.5 * (hi - lo).maxCoeff();
  if (!(out.scale > 0)) out.scale = 1;  // a single point, or all coincident
  CSHAPES_REQUIRE(std::isfinite(out.scale), "Coulomb summation: point coordinates must be finite");
  // In float, 1/r³ must stay finite (< 3e38) even summed over a block: the floor is at least 1e-10 of the
  // half box (1e-12 of the diagonal is raised here), far below any meaningful geometry.
  const double floor = std::max(min_distance / out.scale, 1e-10);
  out.floor2 = static_cast<float>(floor * floor);
  return out;
}

}  // namespace coulomb_detail

CoulombEvaluation coulomb_direct_float(const Points& X, double min_distance, bool want_potentials) {
  using namespace coulomb_detail;
  const Index n = X.rows();
  CSHAPES_REQUIRE(n < (Index(1) << 31) - kBlock, "coulomb_direct_float: too many points (", n, ")");
  const NormalizedPoints norm = normalize_points(X, min_distance);
  // The points in the order of their coordinates (x, then y, then z), so that every float partial sum adds
  // the same terms in the same order however the points are numbered; points with equal coordinates add
  // equal terms. sorted[k]: the point in place k.
  std::vector<Index> sorted(static_cast<size_t>(n));
  std::iota(sorted.begin(), sorted.end(), Index(0));
  std::sort(sorted.begin(), sorted.end(), [&X](Index a, Index b) {
    for (int k = 0; k < 3; ++k)
      if (X(a, k) != X(b, k)) return X(a, k) < X(b, k);
    return false;
  });
  std::vector<float> x(n), y(n), z(n), x_lo(n), y_lo(n), z_lo(n);
  for (Index k = 0; k < n; ++k) {
    const Index i = sorted[static_cast<size_t>(k)];
    split_float((X(i, 0) - norm.center[0]) / norm.scale, x[k], x_lo[k]);
    split_float((X(i, 1) - norm.center[1]) / norm.scale, y[k], y_lo[k]);
    split_float((X(i, 2) - norm.center[2]) / norm.scale, z[k], z_lo[k]);
  }
  std::vector<double> potential(n, 0.0), fx(n, 0.0), fy(n, 0.0), fz(n, 0.0);
  const FloatPoints points{x.data(), y.data(), z.data(), x_lo.data(), y_lo.data(), z_lo.data()};
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
  for (Index k = 0; k < n; ++k) {
    const Index i = sorted[static_cast<size_t>(k)];
    energy += potential[k];
    result.gradient(i, 0) = gradient_scale * fx[k];
    result.gradient(i, 1) = gradient_scale * fy[k];
    result.gradient(i, 2) = gradient_scale * fz[k];
  }
  result.energy = energy / norm.scale;
  if (want_potentials) {
    result.potential.resize(n);
    for (Index k = 0; k < n; ++k)
      result.potential[sorted[static_cast<size_t>(k)]] = potential[k] / norm.scale;
  }
  return result;
}

CoulombEvaluation coulomb_energy_gradient(const Points& X, const CoulombOptions& options,
                                          CoulombFmmTree* fmm_tree) {
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
      return coulomb_fmm(X, fmm, nullptr, fmm_tree);
    }
  }
}

double relative_l2_error(const Points& a, const Points& b) {
  return (a - b).norm() / b.norm();
}

CoulombErrors coulomb_errors(const CoulombEvaluation& evaluation, const CoulombEvaluation& reference) {
  CSHAPES_REQUIRE(evaluation.gradient.rows() == reference.gradient.rows(),
                  "coulomb_errors: ", evaluation.gradient.rows(), " vs ", reference.gradient.rows(),
                  " points");
  CoulombErrors e;
  e.gradient = relative_l2_error(evaluation.gradient, reference.gradient);
  e.energy = std::abs(evaluation.energy - reference.energy) / std::abs(reference.energy);
  return e;
}

CoulombErrors coulomb_errors(const CoulombEvaluation& evaluation, const std::vector<Index>& targets,
                             const CoulombTargetSums& reference) {
  const Index count = static_cast<Index>(targets.size());
  CSHAPES_REQUIRE(reference.gradient.rows() == count && reference.potential.size() == count,
                  "coulomb_errors: the reference has ", reference.gradient.rows(), " rows for ", count,
                  " targets");
  CSHAPES_REQUIRE(evaluation.potential.size() == evaluation.gradient.rows(),
                  "coulomb_errors: the evaluation has no potentials (set want_potentials)");
  double diff2 = 0, ref2 = 0, phi = 0, phi_exact = 0;
  for (Index t = 0; t < count; ++t) {
    const Index i = targets[static_cast<size_t>(t)];
    CSHAPES_REQUIRE(i >= 0 && i < evaluation.gradient.rows(), "coulomb_errors: target ", i, " out of range");
    diff2 += (evaluation.gradient.row(i) - reference.gradient.row(t)).squaredNorm();
    ref2 += reference.gradient.row(t).squaredNorm();
    phi += evaluation.potential[i];
    phi_exact += reference.potential[t];
  }
  CoulombErrors e;
  e.gradient = std::sqrt(diff2 / ref2);
  e.energy = std::abs(phi - phi_exact) / std::abs(phi_exact);
  return e;
}

CoulombOptions::Summation parse_coulomb_summation(const std::string& name) {
  if (name == "auto") return CoulombOptions::Summation::Auto;
  if (name == "direct") return CoulombOptions::Summation::Direct;
  if (name == "direct-float") return CoulombOptions::Summation::DirectFloat;
  if (name == "fast") return CoulombOptions::Summation::Fast;
  fail("unknown Coulomb summation '", name, "'; known: auto, direct, direct-float, fast");
}

std::string to_string(CoulombOptions::Summation summation) {
  switch (summation) {
    case CoulombOptions::Summation::Auto:
      return "auto";
    case CoulombOptions::Summation::Direct:
      return "direct";
    case CoulombOptions::Summation::DirectFloat:
      return "direct-float";
    case CoulombOptions::Summation::Fast:
      return "fast";
  }
  return "auto";
}

}  // namespace cshapes
