#include "cshapes/canon/smacof.h"

#include <omp.h>

#include <Eigen/QR>
#include <algorithm>
#include <cfloat>
#include <cmath>
#include <limits>
#include <string>

#include "cshapes/canon/classical_mds.h"
#include "cshapes/operators/cotangent_operator.h"
#include "cshapes/support/error.h"
#include "cshapes/support/simd.h"
#include "cshapes/support/timing.h"

#include <immintrin.h>

namespace cshapes {
namespace {

#pragma GCC push_options
#pragma GCC target("avx2,fma")
namespace avx2 {
#define CSHAPES_SIMD_VECTOR_AVX2
#include "cshapes/support/simd_vector.inl"
#undef CSHAPES_SIMD_VECTOR_AVX2
#include "cshapes/canon/smacof_row_simd.inl"
}  // namespace avx2
#pragma GCC pop_options

#pragma GCC push_options
#pragma GCC target("avx2,fma,avx512f,avx512vl,avx512dq,avx512bw")
// gcc 12 warns falsely in its own AVX-512 intrinsics (_mm512_undefined_ps initialises a value from itself).
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wmaybe-uninitialized"
// The AVX2 vector type here too (eight lanes, the 12-bit reciprocal square root estimate), compiled with
// AVX-512's registers: the same bytes as the AVX2 target. With 16 lanes and the 14-bit estimate the tosca5k
// forms moved enough to change SMACOF's Hausdorff mAP in the third decimal (0.774 against 0.772), and the
// pass was no faster.
namespace avx512 {
#define CSHAPES_SIMD_VECTOR_AVX2
#include "cshapes/support/simd_vector.inl"
#undef CSHAPES_SIMD_VECTOR_AVX2
#include "cshapes/canon/smacof_row_simd.inl"
}  // namespace avx512
#pragma GCC diagnostic pop
#pragma GCC pop_options

// Tiles of kTileRows × kTileCols entries: float partial sums run over at most kTileCols / 8 (rows) or
// kTileRows (columns) terms before going into double accumulators, and a tile's column accumulators
// (3 × kTileCols floats) stay in L1. Measured at n = 3,505 (one thread): 256 × 256 with software prefetch
// of the row two ahead 0.70 ns per pair, without prefetch 1.0; 128 × 1024 and 512 × 512 are slower.
constexpr Index kTileRows = 256;
constexpr Index kTileCols = 256;
// Rows ahead whose tile segment is prefetched: each row of a tile is a separate 1 KB run of D, and the
// hardware prefetcher alone stalls at the start of every run. The prefetches ride in the row's vector loop
// (one line per two vectors): with a separate loop of them before each row the pass took a sixth longer.
constexpr Index kPrefetchRows = 2;

// The tiles (row block, column block) of an n×n matrix holding some entry (i, j) with i < j.
std::vector<std::pair<Index, Index>> upper_tiles(Index n) {
  const Index row_blocks = (n + kTileRows - 1) / kTileRows, col_blocks = (n + kTileCols - 1) / kTileCols;
  std::vector<std::pair<Index, Index>> tiles;
  for (Index bj = 0; bj < col_blocks; ++bj)
    for (Index bi = 0; bi < row_blocks && bi * kTileRows < std::min(n, (bj + 1) * kTileCols) - 1; ++bi)
      tiles.emplace_back(bi, bj);
  return tiles;
}

// The configuration in single precision, structure of arrays, padded for vector loads.
struct FloatConfiguration {
  std::vector<float> x, y, z, w;
};

// Row accumulators of one row i over one tile: Σⱼ wⱼ cᵢⱼ (xᵢ − xⱼ) and Σⱼ wⱼ (δᵢⱼ − dᵢⱼ)².
struct RowSums {
  double x = 0, y = 0, z = 0, stress = 0;
};

// One row i against columns [ja, jb) of the tile starting at column j0: accumulates the row's sums and,
// into col_{x,y,z}[j − j0], the columns' sums wᵢ cᵢⱼ (xⱼ − xᵢ). cᵢⱼ = δᵢⱼ / dᵢⱼ (0 when dᵢⱼ = 0). The whole
// vectors run the kernel of `target` (canon/smacof_row_simd.inl), the rest the scalar loop below.
template <bool Weighted>
inline RowSums row_pass(SimdTarget target, const float* delta, const float* ahead, const FloatConfiguration& c,
                        Index i, Index ja, Index jb, Index j0, float* col_x, float* col_y, float* col_z) {
  const float xi = c.x[i], yi = c.y[i], zi = c.z[i], wi = Weighted ? c.w[i] : 1.0f;
  const float* xs = c.x.data();
  const float* ys = c.y.data();
  const float* zs = c.z.data();
  const float* ws = c.w.data();
  double vector_sums[4] = {0, 0, 0, 0};
  Index j = ja;
  if (target == SimdTarget::Avx512)
    j = avx512::row_vector_part<Weighted>(delta, ahead, xs, ys, zs, ws, xi, yi, zi, wi, j, jb, j0, col_x,
                                          col_y, col_z, vector_sums);
  else if (target == SimdTarget::Avx2)
    j = avx2::row_vector_part<Weighted>(delta, ahead, xs, ys, zs, ws, xi, yi, zi, wi, j, jb, j0, col_x, col_y,
                                        col_z, vector_sums);
  RowSums sums{vector_sums[0], vector_sums[1], vector_sums[2], vector_sums[3]};
  // The remainder (the whole row on the baseline): the same arithmetic with an exact 1/√.
  for (; j < jb; ++j) {
    const float dlt = delta[j];
    const float dx = xi - xs[j], dy = yi - ys[j], dz = zi - zs[j];
    const float d2 = dx * dx + dy * dy + dz * dz;
    const float inv = d2 > FLT_MIN ? 1.0f / std::sqrt(d2) : 0.0f;
    const float residual = dlt - d2 * inv;
    const float ratio = dlt * inv;
    const float wj = Weighted ? ws[j] : 1.0f;
    const float row_coef = ratio * wj, col_coef = ratio * wi;
    sums.stress += wj * residual * residual;
    sums.x += row_coef * dx;
    sums.y += row_coef * dy;
    sums.z += row_coef * dz;
    col_x[j - j0] -= col_coef * dx;
    col_y[j - j0] -= col_coef * dy;
    col_z[j - j0] -= col_coef * dz;
  }
  return sums;
}

// The pass: σ(X) and S = [Σⱼ wⱼ cᵢⱼ (xᵢ − xⱼ)]ᵢ over the upper triangle, in tiles. Deterministic for any
// thread count: a task is one row block (its tiles left to right); a row's sums over its own tiles are added
// in tile order, each tile's column sums are kept apart and added afterwards in row-block order, and the
// blocks' stresses in block order.
template <bool Weighted>
double stress_and_sums(const DistanceMatrix& D, const FloatConfiguration& config, Points& sums) {
  const Index n = D.rows();
  const Index blocks = (n + kTileRows - 1) / kTileRows;
  static_assert(kTileRows == kTileCols, "row and column blocks must coincide");
  const SimdTarget target = simd_target();
  // Tile (bi, bj), bi ≤ bj, at column_sums[3·kTileCols·tile_index(bi, bj)]: the tiles of row block bi follow
  // those of the blocks above it.
  auto tile_index = [blocks](Index bi, Index bj) { return bi * blocks - bi * (bi - 1) / 2 + (bj - bi); };
  std::vector<float> column_sums(static_cast<size_t>(3 * kTileCols * tile_index(blocks, blocks)), 0.0f);
  std::vector<double> row_sums(3 * static_cast<size_t>(n), 0.0), block_stress(blocks, 0.0);
#pragma omp parallel for schedule(dynamic, 1)
  for (Index bi = 0; bi < blocks; ++bi) {
    const Index i0 = bi * kTileRows, i1 = std::min(n, i0 + kTileRows);
    double stress = 0;
    for (Index bj = bi; bj < blocks; ++bj) {
      const Index j0 = bj * kTileCols, j1 = std::min(n, j0 + kTileCols);
      float* col = column_sums.data() + 3 * kTileCols * tile_index(bi, bj);
      for (Index i = i0; i < i1; ++i) {
        const Index ja = std::max(j0, i + 1);
        if (ja >= j1) continue;
        // The row kPrefetchRows ahead in this tile (its entries lie within this row's range), else this one.
        const float* ahead = D.data() + (i + kPrefetchRows < i1 ? i + kPrefetchRows : i) * n;
        const RowSums r = row_pass<Weighted>(target, D.data() + i * n, ahead, config, i, ja, j1, j0, col,
                                             col + kTileCols, col + 2 * kTileCols);
        row_sums[i] += r.x;
        row_sums[n + i] += r.y;
        row_sums[2 * n + i] += r.z;
        stress += Weighted ? static_cast<double>(config.w[i]) * r.stress : r.stress;
      }
    }
    block_stress[bi] = stress;
  }
  sums.resize(n, 3);
  // Column j's sum: its row sum, then its tiles' column sums in row-block order. The loops run over j
  // innermost (contiguous in both arrays, so they vectorise) without changing any sum's order of additions.
#pragma omp parallel for schedule(static)
  for (Index bj = 0; bj < blocks; ++bj) {
    const Index j0 = bj * kTileCols, width = std::min(n, j0 + kTileCols) - j0;
    for (int k = 0; k < 3; ++k) {
      double* s = sums.col(k).data() + j0;
      const double* r = row_sums.data() + k * n + j0;
      for (Index j = 0; j < width; ++j) s[j] = r[j];
      for (Index bi = 0; bi <= bj; ++bi) {
        const float* tile = column_sums.data() + 3 * kTileCols * tile_index(bi, bj) + k * kTileCols;
        for (Index j = 0; j < width; ++j) s[j] += static_cast<double>(tile[j]);
      }
    }
  }
  double stress = 0;
  for (const double s : block_stress) stress += s;
  return stress;
}

// Validity of the weights: n finite positive values, or none.
void check_weights(const Eigen::VectorXd& weights, Index n) {
  if (weights.size() == 0) return;
  CSHAPES_REQUIRE(weights.size() == n, "SMACOF: ", weights.size(), " vertex weights given for ", n,
                  " vertices");
  for (Index i = 0; i < n; ++i)
    CSHAPES_REQUIRE(std::isfinite(weights[i]) && weights[i] > 0, "SMACOF: vertex weight ", i, " is ",
                    weights[i], "; weights must be finite and positive");
}

// Evaluates passes over D for one problem (fixed D and weights) and counts them.
class Evaluator {
 public:
  Evaluator(const DistanceMatrix& D, const Eigen::VectorXd& weights) : D_(D), weights_(weights) {
    const Index n = D.rows();
    const Index padded = n + 8;
    config_.x.assign(padded, 0.0f);
    config_.y.assign(padded, 0.0f);
    config_.z.assign(padded, 0.0f);
    config_.w.assign(padded, 1.0f);
    weight_sum_ = static_cast<double>(n);
    if (weights.size()) {
      for (Index i = 0; i < n; ++i) config_.w[i] = static_cast<float>(weights[i]);
      weight_sum_ = weights.sum();
    }
  }

  // Weighted centroid of X, the origin of the float coordinates (translation changes neither σ nor X⁺).
  Eigen::RowVector3d centroid(const Points& X) const {
    if (weights_.size()) return (weights_.transpose() * X) / weight_sum_;
    return X.colwise().mean();
  }

  GuttmanTransform operator()(const Points& X) {
    ++passes_;
    const Index n = D_.rows();
    Eigen::RowVector3d origin = centroid(X);
    for (Index i = 0; i < n; ++i) {
      config_.x[i] = static_cast<float>(X(i, 0) - origin[0]);
      config_.y[i] = static_cast<float>(X(i, 1) - origin[1]);
      config_.z[i] = static_cast<float>(X(i, 2) - origin[2]);
    }
    GuttmanTransform out;
    Points sums;
    out.stress = weights_.size() ? stress_and_sums<true>(D_, config_, sums)
                                 : stress_and_sums<false>(D_, config_, sums);
    out.X_next = sums / weight_sum_;
    // Exactly weighted-centred in exact arithmetic; float partial sums leave a drift of ~1e-8 to remove.
    out.X_next.rowwise() -= centroid(out.X_next);
    return out;
  }
  int passes() const { return passes_; }

 private:
  const DistanceMatrix& D_;
  const Eigen::VectorXd& weights_;
  FloatConfiguration config_;
  double weight_sum_ = 0;
  int passes_ = 0;
};

// Σ_{i<j} wᵢwⱼ δᵢⱼ², after checking D (same checks as validate_distance_matrix).
double weighted_distance_energy(const DistanceMatrix& D, const Eigen::VectorXd& weights,
                                const std::string& what) {
  const Index n = D.rows();
  CSHAPES_REQUIRE(D.rows() == D.cols(), what, ": distance matrix must be square, got ", D.rows(), "x",
                  D.cols());
  CSHAPES_REQUIRE(n >= 4, what, ": needs at least 4 points for a 3-D embedding, got ", n);
  const auto tiles = upper_tiles(n);
  std::vector<double> tile_energies(tiles.size(), 0.0);  // summed in tile order: deterministic
  // First offending pair (i, j), i < j, in tile order; kind 1: not finite or negative, 2: asymmetric.
  Index bad_i = -1, bad_j = -1;
  int bad_kind = 0;
  size_t bad_tile = tiles.size();
#pragma omp parallel for schedule(dynamic, 1)
  for (size_t t = 0; t < tiles.size(); ++t) {
    const Index i0 = tiles[t].first * kTileRows, i1 = std::min(n, i0 + kTileRows);
    const Index j0 = tiles[t].second * kTileCols, j1 = std::min(n, j0 + kTileCols);
    double tile_energy = 0;
    for (Index i = i0; i < i1; ++i) {
      const double wi = weights.size() ? weights[i] : 1.0;
      for (Index j = std::max(j0, i + 1); j < j1; ++j) {
        const float a = D(j, i), b = D(i, j);
        int kind = 0;
        if (!(a >= 0 && a <= FLT_MAX))
          kind = 1;
        else if (std::abs(a - b) > 1e-5f * std::max(a, b) || !(b >= 0))
          kind = 2;
        if (kind) {
#pragma omp critical(cshapes_smacof_bad)
          if (t < bad_tile) {
            bad_tile = t;
            bad_i = i;
            bad_j = j;
            bad_kind = kind;
          }
          i = i1;  // stop this tile
          break;
        }
        const double wj = weights.size() ? weights[j] : 1.0;
        tile_energy += wi * wj * static_cast<double>(a) * static_cast<double>(a);
      }
    }
    tile_energies[t] = tile_energy;
  }
  double energy = 0;
  for (const double e : tile_energies) energy += e;
  if (bad_kind == 1) {
    fail(what, ": distance (", bad_i, ", ", bad_j, ") is ", D(bad_j, bad_i),
         "; distances must be finite and non-negative", bad_distance_hint(D, bad_j, bad_i));
  }
  if (bad_kind == 2)
    fail(what, ": distance matrix is not symmetric: (", bad_i, ", ", bad_j, ") is ", D(bad_j, bad_i),
         " but (", bad_j, ", ", bad_i, ") is ", D(bad_i, bad_j));
  CSHAPES_REQUIRE(energy > 0, what, ": all distances are zero");
  return energy;
}

// Extrapolated configuration from iterates x₀ … x_K (K ≥ 2) of a fixed-point iteration, u_j = x_{j+1} − x_j:
//   RRE: γ = argmin ‖Σ γⱼ uⱼ‖ subject to Σ γⱼ = 1;  MPE: c = argmin ‖Σ_{j<K−1} cⱼ uⱼ + u_{K−1}‖, γ = c / Σc.
// Returns Σ γⱼ x_{j+1} (the combination advanced by one step), or an empty matrix when degenerate.
Points extrapolate(const std::vector<Points>& iterates, SmacofAcceleration method) {
  const int K = static_cast<int>(iterates.size()) - 1;
  const Index m = iterates[0].size();
  Eigen::MatrixXd U(m, K);
  for (int j = 0; j < K; ++j)
    U.col(j) = Eigen::Map<const Eigen::VectorXd>((iterates[j + 1] - iterates[j]).eval().data(), m);
  Eigen::VectorXd gamma(K);
  const Eigen::VectorXd last = U.col(K - 1);
  if (method == SmacofAcceleration::Rre) {
    // Eliminate the constraint: γ_{K−1} = 1 − Σ_{j<K−1} γⱼ, so Uγ = u_{K−1} + Σ_{j<K−1} γⱼ (uⱼ − u_{K−1}).
    Eigen::MatrixXd A = U.leftCols(K - 1).colwise() - last;
    Eigen::VectorXd g = A.colPivHouseholderQr().solve(-last);
    gamma.head(K - 1) = g;
    gamma[K - 1] = 1 - g.sum();
  } else {
    Eigen::VectorXd c = U.leftCols(K - 1).colPivHouseholderQr().solve(-last);
    const double total = c.sum() + 1;
    if (!(std::abs(total) > 1e-12)) return {};
    gamma.head(K - 1) = c / total;
    gamma[K - 1] = 1 / total;
  }
  if (!gamma.allFinite()) return {};
  Points s = Points::Zero(iterates[0].rows(), 3);
  for (int j = 0; j < K; ++j) s += gamma[j] * iterates[j + 1];
  return s;
}

}  // namespace

SmacofAcceleration parse_smacof_acceleration(const std::string& name) {
  if (name == "none") return SmacofAcceleration::None;
  if (name == "rre") return SmacofAcceleration::Rre;
  if (name == "mpe") return SmacofAcceleration::Mpe;
  fail("unknown SMACOF acceleration '", name, "'; known: none, rre, mpe");
}

std::string to_string(SmacofAcceleration acceleration) {
  switch (acceleration) {
    case SmacofAcceleration::None:
      return "none";
    case SmacofAcceleration::Rre:
      return "rre";
    case SmacofAcceleration::Mpe:
      return "mpe";
  }
  return "?";
}

void validate_distance_matrix(const DistanceMatrix& D, const std::string& what) {
  weighted_distance_energy(D, {}, what);
}

GuttmanTransform guttman_transform(const DistanceMatrix& D, const Points& X, const Eigen::VectorXd& weights) {
  CSHAPES_REQUIRE(D.rows() == D.cols() && X.rows() == D.rows(), "SMACOF: configuration has ", X.rows(),
                  " points for a ", D.rows(), "x", D.cols(), " distance matrix");
  check_weights(weights, D.rows());
  Evaluator evaluate(D, weights);
  return evaluate(X);
}

namespace {

// One SMACOF run: the current configuration and its evaluation, the history, and the two iterations (plain
// Guttman steps, or cycles of K steps closed by an extrapolation that is kept when it lowers the stress).
class SmacofRun {
 public:
  SmacofRun(const DistanceMatrix& D, const SmacofOptions& options, double energy)
      : options_(options), energy_(energy), evaluate_(D, options.vertex_weights) {}

  // Runs from X0 (centred first) until converged, the target stress or the pass budget.
  void run(const Points& X0) {
    X_ = X0.rowwise() - evaluate_.centroid(X0);
    current_ = evaluate_(X_);
    accept(X_, current_, false);
    if (options_.acceleration == SmacofAcceleration::None)
      run_plain();
    else
      run_extrapolated();
  }

  SmacofResult& result() { return result_; }
  const Points& X() const { return X_; }
  const GuttmanTransform& current() const { return current_; }
  int passes() const { return evaluate_.passes(); }

 private:
  void accept(Points configuration, GuttmanTransform evaluation, bool extrapolated) {
    X_ = std::move(configuration);
    current_ = std::move(evaluation);
    result_.stress_history.push_back(current_.stress / energy_);
    result_.passes_history.push_back(evaluate_.passes());
    result_.extrapolated_history.push_back(extrapolated);
    if (options_.progress)
      options_.progress("smacof", std::min(evaluate_.passes() - 1, options_.max_iterations),
                        options_.max_iterations);
  }
  // Stops for the target and the pass budget; convergence is checked by each mode.
  bool out_of_budget() {
    if (options_.target_stress > 0 && current_.stress / energy_ <= options_.target_stress) {
      result_.stop_reason = "target stress";
      return true;
    }
    if (evaluate_.passes() - 1 >= options_.max_iterations) {
      result_.stop_reason = "max iterations";
      return true;
    }
    return false;
  }
  bool converged(double before, double after, int passes) {
    if (options_.tolerance > 0 && before > 0 && (before - after) / before < options_.tolerance * passes) {
      result_.stop_reason = "converged";
      return true;
    }
    return false;
  }
  void step() {
    Points next = current_.X_next;
    GuttmanTransform evaluation = evaluate_(next);
    accept(std::move(next), std::move(evaluation), false);
  }

  void run_plain() {
    while (!out_of_budget()) {
      const double before = current_.stress;
      step();
      if (converged(before, current_.stress, 1)) break;
    }
  }

  void run_extrapolated() {
    const int K = options_.extrapolation_window;
    while (!out_of_budget()) {
      const double cycle_start = current_.stress;
      const int cycle_passes = evaluate_.passes();
      std::vector<Points> iterates{X_};
      for (int m = 1; m < K; ++m) {
        iterates.push_back(current_.X_next);
        step();
        if (out_of_budget()) return;
      }
      iterates.push_back(current_.X_next);  // x_K, not evaluated yet
      Points extrapolated = extrapolate(iterates, options_.acceleration);
      bool accepted = false;
      if (extrapolated.size() && extrapolated.allFinite()) {
        GuttmanTransform evaluation = evaluate_(extrapolated);
        if (evaluation.stress < current_.stress) {
          accept(std::move(extrapolated), std::move(evaluation), true);
          ++result_.extrapolations_accepted;
          accepted = true;
        } else {
          ++result_.extrapolations_rejected;
          if (out_of_budget()) return;
        }
      }
      if (!accepted) {
        Points next = iterates.back();
        GuttmanTransform evaluation = evaluate_(next);
        accept(std::move(next), std::move(evaluation), false);
      }
      if (converged(cycle_start, current_.stress, evaluate_.passes() - cycle_passes)) return;
    }
  }

  const SmacofOptions& options_;
  const double energy_;
  Evaluator evaluate_;
  Points X_;
  GuttmanTransform current_;
  SmacofResult result_;
};

}  // namespace

SmacofResult smacof(const DistanceMatrix& D, const Points& X0, const SmacofOptions& options) {
  const WallClock::time_point start = WallClock::now();
  CSHAPES_REQUIRE(X0.rows() == D.rows(), "SMACOF: initial configuration has ", X0.rows(), " points for a ",
                  D.rows(), "x", D.cols(), " distance matrix");
  CSHAPES_REQUIRE(X0.allFinite(), "SMACOF: initial configuration has non-finite coordinates");
  check_limit(smacof_limits::kIterations, options.max_iterations, "SMACOF");
  check_limit(smacof_limits::kTolerance, options.tolerance, "SMACOF");
  check_limit(smacof_limits::kWindow, options.extrapolation_window, "SMACOF");
  check_weights(options.vertex_weights, D.rows());
  const double energy = weighted_distance_energy(D, options.vertex_weights, "SMACOF");

  SmacofRun run(D, options, energy);
  const WallClock::time_point iterations_start = WallClock::now();
  const double cpu_start = process_cpu_seconds();
  run.run(X0);

  if (options.progress) options.progress("smacof", options.max_iterations, options.max_iterations);  // done
  SmacofResult result = std::move(run.result());
  result.X = run.X();
  result.stress = run.current().stress;
  result.normalized_stress = run.current().stress / energy;
  result.iterations = run.passes() - 1;
  result.seconds = seconds_since(start);
  result.seconds_per_iteration = seconds_since(iterations_start) / run.passes();
  result.cpu_seconds_per_iteration = (process_cpu_seconds() - cpu_start) / run.passes();
  return result;
}

SmacofResult smacof(const DistanceMatrix& D, const SmacofOptions& options) {
  ClassicalMdsOptions cmds;
  cmds.most_negative_eigenvalue = false;
  return smacof(D, classical_mds(D, cmds).X, options);
}

Eigen::VectorXd vertex_area_weights(const Mesh& mesh) {
  const Index n = mesh.num_vertices();
  const Eigen::VectorXd area = lumped_mass(mesh);  // operators/cotangent_operator.h
  for (Index i = 0; i < n; ++i)
    CSHAPES_REQUIRE(area[i] > 0, "SMACOF area weights: vertex ", i, " is in no triangle of positive area");
  return area / area.mean();
}

}  // namespace cshapes
