#include "cshapes/matching/icp.h"

#include <omp.h>

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <exception>
#include <limits>
#include <numeric>
#include <random>

#include "cshapes/support/error.h"
#include "cshapes/support/morton.h"
#include "cshapes/support/timing.h"
#include "cshapes/mesh/unit_scale.h"

namespace cshapes {

// ---------------------------------------------------------------------------------------------------------
// Shapes prepared for ICP

namespace {

// Row order of X along a Morton (Z-order) curve over its bounding box.
std::vector<int> spatial_order(const Points& X) {
  Eigen::RowVector3d lo = X.colwise().minCoeff(), hi = X.colwise().maxCoeff();
  double extent = std::max((hi - lo).maxCoeff(), 1e-300);
  std::vector<std::pair<uint64_t, int32_t>> keyed(static_cast<size_t>(X.rows()));
  for (Index i = 0; i < X.rows(); ++i) {
    Eigen::RowVector3d u = (X.row(i) - lo) / extent * 1023.0;  // 10 bits per axis
    uint64_t key = 0;
    for (int c = 0; c < 3; ++c) key |= morton_spread_bits(static_cast<uint64_t>(u[c])) << c;
    keyed[static_cast<size_t>(i)] = {key, static_cast<int32_t>(i)};
  }
  radix_sort_by_key(keyed, 30);  // stable: equal codes keep the row order
  std::vector<int> order(keyed.size());
  for (size_t k = 0; k < keyed.size(); ++k) order[k] = keyed[k].second;
  return order;
}

// The covariance of points already centred: six dot products of columns (cheaper than a general matrix
// product here).
Eigen::Matrix3d covariance_of_centred(const Points& centred) {
  Eigen::Matrix3d covariance;
  for (int a = 0; a < 3; ++a)
    for (int b = a; b < 3; ++b)
      covariance(a, b) = covariance(b, a) =
          centred.col(a).dot(centred.col(b)) / static_cast<double>(centred.rows());
  return covariance;
}

}  // namespace

std::string icp_points_refusal(const Points& points) {
  const Index n = points.rows();
  if (n < 4) return detail::concat("ICP needs at least 4 points that span a plane, got ", n);
  if (!points.allFinite()) return "ICP: the point set has non-finite coordinates";
  // Rounding: the centring itself leaves a few ulps of the coordinates' magnitude (50 copies of one point do
  // not centre to exact zeros), and a spread below that says nothing about the shape.
  constexpr double kRounding = 1024 * std::numeric_limits<double>::epsilon();
  const double magnitude = points.cwiseAbs().maxCoeff();
  Points centred = points.rowwise() - points.colwise().mean();
  if (!(centred.cwiseAbs().maxCoeff() > kRounding * magnitude))
    return detail::concat("ICP needs points that span a plane; these ", n, " points lie at one point");
  // At unit size (exact: a power of two), where the covariance neither overflows nor underflows.
  const double scale = power_of_two_unit_scale(centred);
  centred *= scale;
  const Eigen::Matrix3d covariance = covariance_of_centred(centred);
  const Eigen::Vector3d variances =  // increasing
      Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d>(covariance, Eigen::EigenvaluesOnly).eigenvalues();
  const double along = std::sqrt(std::max(variances[2], 0.0)), across = std::sqrt(std::max(variances[1], 0.0));
  if (across > 1e-10 * along && across > kRounding * magnitude * scale) return "";
  return detail::concat("ICP needs points that span a plane; these ", n, " points lie on one line");
}

std::string icp_size_refusal(const Points& points) {
  if (points.rows() == 0) return "";
  const double radius = (points.rowwise() - points.colwise().mean()).cwiseAbs().maxCoeff();
  if (radius >= kIcpSmallestSize && radius <= kIcpLargestSize) return "";
  return detail::concat("ICP: the points reach ", radius,
                        " from their centroid, outside the sizes whose squared distances a double holds (",
                        kIcpSmallestSize, " to ", kIcpLargestSize, "); scale the shapes");
}

IcpShape::IcpShape(const Points& points, const IcpOptions& options)
    : points_(points), pyramid_(options.pyramid), seed_(options.seed) {
  const Index n = points.rows();
  if (std::string refusal = icp_points_refusal(points); !refusal.empty()) fail(refusal);
  centroid_ = points.colwise().mean().transpose();
  Points centred = points.rowwise() - centroid_.transpose();
  // ICP works on squared distances: beyond these sizes they overflow or underflow (a shape of size 1e154
  // was refused as "points on a line"). Refused by its size, so that the caller can name the shape.
  if (std::string refusal = icp_size_refusal(points); !refusal.empty()) fail(refusal);
  const Eigen::Matrix3d covariance = covariance_of_centred(centred);
  Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eig(covariance);
  // Eigen sorts increasing; principal axes go by decreasing variance.
  variances_ = eig.eigenvalues().reverse();
  axes_ = eig.eigenvectors().rowwise().reverse();
  if (axes_.determinant() < 0) axes_.col(2) *= -1;
  rms_radius_ = std::sqrt(std::max(covariance.trace(), 0.0));

  auto make_level = [&](std::vector<int> indices) {
    auto level = std::make_shared<Level>();
    level->indices = std::move(indices);
    level->centred.resize(static_cast<Index>(level->indices.size()), 3);
    for (size_t k = 0; k < level->indices.size(); ++k)
      level->centred.row(static_cast<Index>(k)) = centred.row(level->indices[k]);
    return std::shared_ptr<const Level>(std::move(level));
  };
  const std::vector<int> spatial = spatial_order(centred);
  std::vector<int> spatial_rank(static_cast<size_t>(n));
  for (size_t k = 0; k < spatial.size(); ++k)
    spatial_rank[static_cast<size_t>(spatial[k])] = static_cast<int>(k);
  std::shared_ptr<const Level> full = make_level(spatial);
  tree_ = std::make_unique<NearestNeighbors>(full->centred);

  // Nested random subsamples: the first m entries of one random permutation, stored in spatial order.
  std::vector<int> shuffled(static_cast<size_t>(n));
  std::iota(shuffled.begin(), shuffled.end(), 0);
  std::mt19937_64 rng(options.seed);
  std::shuffle(shuffled.begin(), shuffled.end(), rng);
  Index previous = 0;
  for (Index m : options.pyramid) {
    CSHAPES_REQUIRE(m > previous, "IcpOptions::pyramid must increase, got ", m, " after ", previous);
    previous = m;
    if (m >= n) {
      levels_.push_back(full);
      continue;
    }
    std::vector<int> sample(shuffled.begin(), shuffled.begin() + m);
    std::sort(sample.begin(), sample.end(), [&](int a, int b) {
      return spatial_rank[static_cast<size_t>(a)] < spatial_rank[static_cast<size_t>(b)];
    });
    levels_.push_back(make_level(std::move(sample)));
  }
  levels_.push_back(full);
}

// ---------------------------------------------------------------------------------------------------------
// ICP

namespace {

void check_options(const IcpOptions& o) {
  check_limit(icp_limits::kTrim, o.trim_fraction, "ICP");
  check_limit(icp_limits::kTolerance, o.relative_tolerance, "ICP");
  CSHAPES_REQUIRE(o.max_iterations >= 1, "ICP max_iterations must be >= 1");
  CSHAPES_REQUIRE(o.screening_iterations >= 0, "ICP screening_iterations must be >= 0");
  CSHAPES_REQUIRE(o.finalists >= 1, "ICP finalists must be >= 1");
  CSHAPES_REQUIRE(o.relative_tolerance >= 0 && o.absolute_tolerance >= 0, "ICP tolerances must be >= 0");
  CSHAPES_REQUIRE(o.max_correspondence_distance > 0, "ICP max_correspondence_distance must be > 0");
}

// The state of one start: a transform between the CENTRED sets, and the determinant it keeps.
struct Track {
  RigidTransform T;
  int determinant = 1;
  double rmse = std::numeric_limits<double>::infinity();
  int iterations = 0;        // on the current level
  int total_iterations = 0;  // on every level
  std::string stop_reason;
  bool converged = false;
  double inlier_fraction = 1;
  std::vector<double> history;  // on the current level
  // The nearest neighbours (level rows) and squared distances of the last correspondence pass;
  // `current` when they belong to T (the loop stopped before updating T); `level`: whose queries they are.
  Eigen::VectorXi nn_st, nn_ts;
  Eigen::VectorXd d2_st, d2_ts;
  bool current = false;
  int level = -1;
};

// Marks (keep[i] = 1) the pairs of one direction whose squared distance passes the trimming and distance
// limits. Returns the number kept.
Index keep_pairs(const Eigen::VectorXd& d2, double trim_fraction, double max_d2, std::vector<double>& scratch,
                 std::vector<char>& keep) {
  const Index m = d2.size();
  double threshold = max_d2;
  if (trim_fraction > 0 && m > 1) {
    scratch.assign(d2.data(), d2.data() + m);
    Index kept =
        std::max<Index>(1, static_cast<Index>(std::floor((1.0 - trim_fraction) * static_cast<double>(m))));
    std::nth_element(scratch.begin(), scratch.begin() + (kept - 1), scratch.end());
    threshold = std::min(threshold, scratch[static_cast<size_t>(kept - 1)]);
  }
  keep.assign(static_cast<size_t>(m), 0);
  Index count = 0;
  for (Index i = 0; i < m; ++i)
    if (d2[i] <= threshold) {
      keep[static_cast<size_t>(i)] = 1;
      ++count;
    }
  return count;
}

// For each row of level `fine`: the row of level `coarse` holding the same point, or −1.
std::vector<int> carried_rows(const IcpShape& shape, int coarse, int fine) {
  std::vector<int> coarse_row(static_cast<size_t>(shape.size()), -1);
  const std::vector<int>& coarse_indices = shape.level_indices(coarse);
  for (size_t k = 0; k < coarse_indices.size(); ++k)
    coarse_row[static_cast<size_t>(coarse_indices[k])] = static_cast<int>(k);
  const std::vector<int>& fine_indices = shape.level_indices(fine);
  std::vector<int> rows(fine_indices.size());
  for (size_t k = 0; k < fine_indices.size(); ++k) rows[k] = coarse_row[static_cast<size_t>(fine_indices[k])];
  return rows;
}

// One direction's nearest-neighbour searches: for each query row i, the tree's nearest point to query(i).
// Every search is bounded by a nearby point's distance: when `hinted` (from the second pass on), the query's
// own last neighbour (the pose moved a little); else the previous query's neighbour (queries are in Morton
// order, so consecutive ones are close). With `carry`, a query whose row the previous level searched at the
// same pose (carried[i] ≥ 0) takes that result instead.
template <class Query>
void search_direction(Index queries, const NearestNeighbors& tree, Query query, bool hinted, bool carry,
                      const std::vector<int>& carried, const Eigen::VectorXi& old_nn,
                      const Eigen::VectorXd& old_d2, Eigen::VectorXi& nn, Eigen::VectorXd& d2) {
  for (Index i = 0; i < queries; ++i) {
    if (carry && carried[static_cast<size_t>(i)] >= 0) {
      nn[i] = old_nn[carried[static_cast<size_t>(i)]];
      d2[i] = old_d2[carried[static_cast<size_t>(i)]];
      continue;
    }
    Eigen::Vector3d q = query(i);
    nn[i] = static_cast<int>(hinted  ? tree.nearest(q, nn[i], &d2[i])
                             : i > 0 ? tree.nearest(q, nn[i - 1], &d2[i])
                                     : tree.nearest(q, &d2[i]));
  }
}

// The kept pairs (x, y) of one pass: x from the source (centred, untransformed), y from the target (centred),
// visited through their indices rather than gathered into matrices.
struct KeptPairs {
  const Points &S, &T_all, &S_all, &Tg;
  const Eigen::VectorXi &nn_st, &nn_ts;
  const std::vector<char>&keep_st, &keep_ts;
  bool symmetric;
  template <class F>
  void for_each(F&& f) const {
    for (Index i = 0; i < S.rows(); ++i)
      if (keep_st[static_cast<size_t>(i)]) f(S, i, T_all, nn_st[i]);
    if (symmetric)
      for (Index j = 0; j < Tg.rows(); ++j)
        if (keep_ts[static_cast<size_t>(j)]) f(S_all, nn_ts[j], Tg, j);
  }
};

// The closed-form rigid motion of the kept pairs (best_rigid_transform with unit weights, without gathering
// the pairs into matrices): means first, then the cross-covariance of the centred pairs (two passes keep it
// accurate); the rotation has the given determinant.
RigidTransform fit_kept_pairs(const KeptPairs& pairs, Index kept, int determinant) {
  Eigen::Vector3d x_sum = Eigen::Vector3d::Zero(), y_sum = Eigen::Vector3d::Zero();
  pairs.for_each([&](const Points& X, Index a, const Points& Y, Index b) {
    x_sum += X.row(a).transpose();
    y_sum += Y.row(b).transpose();
  });
  const Eigen::Vector3d x_mean = x_sum / static_cast<double>(kept), y_mean = y_sum / static_cast<double>(kept);
  Eigen::Matrix3d H = Eigen::Matrix3d::Zero();
  pairs.for_each([&](const Points& X, Index a, const Points& Y, Index b) {
    H.noalias() += (X.row(a).transpose() - x_mean) * (Y.row(b) - y_mean.transpose());
  });
  RigidTransform T;
  T.rotation = closest_orthogonal_matrix(H, determinant);
  T.translation = y_mean - T.rotation * x_mean;
  return T;
}

// The neighbours of the previous level's last pass, when it saw the current pose: its queries are a subset
// of this level's (the subsamples are nested), so their neighbours are carried over rather than searched
// again. Takes the track's arrays (they are refilled for the new level).
struct CarriedNeighbours {
  bool active = false;
  std::vector<int> rows_st, rows_ts;  // per query row of the new level: its row in the old arrays, or −1
  Eigen::VectorXi nn_st, nn_ts;
  Eigen::VectorXd d2_st, d2_ts;

  CarriedNeighbours(Track& track, const IcpShape& source, const IcpShape& target, int level)
      : active(track.current && track.level >= 0 && track.level < level) {
    if (!active) return;
    rows_st = carried_rows(source, track.level, level);
    rows_ts = carried_rows(target, track.level, level);
    nn_st.swap(track.nn_st);
    nn_ts.swap(track.nn_ts);
    d2_st.swap(track.d2_st);
    d2_ts.swap(track.d2_ts);
  }
};

// Runs ICP steps on one level until a stopping rule (or `max_steps`), updating the track.
void iterate(Track& track, const IcpShape& source, const IcpShape& target, int level, int max_steps,
             const IcpOptions& o) {
  // Queries: the level's samples; partners: searched among ALL points of the other set, so the RMSE of a
  // level estimates the full RMSE without the bias of matching two independent samples (which would hide
  // small differences, e.g. between a pose and its mirror image on a nearly symmetric shape).
  const Points& S = source.level_points(level);
  const Points& Tg = target.level_points(level);
  const Points& S_all = source.level_points(source.num_levels() - 1);
  const Points& T_all = target.level_points(target.num_levels() - 1);
  const double exact = o.absolute_tolerance * target.rms_radius();
  const double max_d2 = o.max_correspondence_distance * o.max_correspondence_distance;

  track.iterations = 0;
  track.history.clear();
  track.converged = false;
  track.stop_reason = "max iterations";
  std::vector<double> scratch;
  std::vector<char> keep_st, keep_ts;
  const CarriedNeighbours carried(track, source, target, level);
  track.current = false;
  track.level = level;
  Eigen::VectorXi& nn_st = track.nn_st;
  Eigen::VectorXi& nn_ts = track.nn_ts;
  Eigen::VectorXd& d2_st = track.d2_st;
  Eigen::VectorXd& d2_ts = track.d2_ts;
  nn_st.resize(S.rows());
  d2_st.resize(S.rows());
  nn_ts.resize(o.symmetric ? Tg.rows() : 0);
  d2_ts.resize(o.symmetric ? Tg.rows() : 0);
  const KeptPairs pairs{S, T_all, S_all, Tg, nn_st, nn_ts, keep_st, keep_ts, o.symmetric};
  double previous = std::numeric_limits<double>::infinity();
  for (int step = 0; step < max_steps; ++step) {
    report_progress_in_parallel(o.progress, "", 0, 0);  // a poll: the step's searches are the long part
    const bool hinted = step > 0;
    const Eigen::Matrix3d& R = track.T.rotation;
    const Eigen::Vector3d& t = track.T.translation;
    // source → target: nearest target point to R·x + t.
    search_direction(
        S.rows(), target.tree(), [&](Index i) -> Eigen::Vector3d { return R * S.row(i).transpose() + t; },
        hinted, carried.active && step == 0, carried.rows_st, carried.nn_st, carried.d2_st, nn_st, d2_st);
    Index kept = keep_pairs(d2_st, o.trim_fraction, max_d2, scratch, keep_st);
    Index total = S.rows();
    // target → source: the nearest transformed source point to y is the nearest source point to Rᵀ(y − t),
    // so the source tree is built once and never moved.
    if (o.symmetric) {
      search_direction(
          Tg.rows(), source.tree(),
          [&](Index j) -> Eigen::Vector3d { return R.transpose() * (Tg.row(j).transpose() - t); }, hinted,
          carried.active && step == 0 && carried.nn_ts.size() > 0, carried.rows_ts, carried.nn_ts,
          carried.d2_ts, nn_ts, d2_ts);
      kept += keep_pairs(d2_ts, o.trim_fraction, max_d2, scratch, keep_ts);
      total += Tg.rows();
    }
    if (kept == 0)
      fail("ICP: no correspondence within max_correspondence_distance = ", o.max_correspondence_distance);
    double sum_d2 = 0;
    for (Index i = 0; i < S.rows(); ++i)
      if (keep_st[static_cast<size_t>(i)]) sum_d2 += d2_st[i];
    if (o.symmetric)
      for (Index j = 0; j < Tg.rows(); ++j)
        if (keep_ts[static_cast<size_t>(j)]) sum_d2 += d2_ts[j];
    // The RMSE of the current pose's pairs; the step below can only lower it for these pairs.
    double rmse = std::sqrt(sum_d2 / static_cast<double>(kept));
    track.rmse = rmse;
    track.inlier_fraction = static_cast<double>(kept) / static_cast<double>(total);
    track.history.push_back(rmse);
    if (rmse <= exact) {
      track.converged = track.current = true;
      track.stop_reason = "exact fit";
      break;
    }
    if (std::isfinite(previous) && std::abs(previous - rmse) <= o.relative_tolerance * previous) {
      track.converged = track.current = true;
      track.stop_reason = "relative change";
      break;
    }
    previous = rmse;
    track.T = fit_kept_pairs(pairs, kept, track.determinant);
    ++track.iterations;
    ++track.total_iterations;
  }
}

// Runs f(k) for k in [0, n), on OpenMP threads when allowed; rethrows the first exception.
template <class F>
void for_each_start(int n, bool parallel, F&& f) {
  std::exception_ptr error;
#pragma omp parallel for schedule(dynamic, 1) if (parallel && !omp_in_parallel() && n > 1)
  for (int k = 0; k < n; ++k) {
    try {
      f(k);
    } catch (...) {
#pragma omp critical(cshapes_icp_error)
      if (!error) error = std::current_exception();
    }
  }
  if (error) std::rethrow_exception(error);
}

}  // namespace

std::vector<RigidTransform> icp_starts(const IcpShape& source, const IcpShape& target, const IcpOptions& o) {
  std::vector<RigidTransform> starts;
  // Axis orders: the identity, then (with swaps) each pair of principal axes exchanged.
  std::vector<Eigen::Matrix3d> orders = {Eigen::Matrix3d::Identity()};
  if (o.try_axis_swaps) {
    for (int a = 0; a < 3; ++a) {
      Eigen::Matrix3d P = Eigen::Matrix3d::Identity();
      int b = (a + 1) % 3, c = (a + 2) % 3;
      P.row(b).swap(P.row(c));
      orders.push_back(P);
    }
  }
  // Source axis k maps to target axis k (up to sign): R = A_t · diag(s) · Perm · A_sᵀ.
  if (!o.try_principal_axes) orders.clear();
  for (const Eigen::Matrix3d& order : orders) {
    for (int signs = 0; signs < 8; ++signs) {
      Eigen::Vector3d s((signs & 1) ? -1.0 : 1.0, (signs & 2) ? -1.0 : 1.0, (signs & 4) ? -1.0 : 1.0);
      RigidTransform T;
      T.rotation = target.principal_axes() * s.asDiagonal() * order * source.principal_axes().transpose();
      if (T.is_reflection() && !o.allow_reflections) continue;
      starts.push_back(T);
    }
  }
  if (o.try_identity) starts.push_back(RigidTransform{});
  CSHAPES_REQUIRE(!starts.empty(),
                  "ICP: no starting pose (try_principal_axes and try_identity are both off)");
  return starts;
}

IcpResult icp(const IcpShape& source, const IcpShape& target, const IcpOptions& o) {
  const WallClock::time_point clock_start = WallClock::now();
  check_options(o);
  CSHAPES_REQUIRE(source.num_levels() >= 1 && target.num_levels() >= 1, "ICP: shapes not prepared");

  IcpResult result;
  result.start_transforms = icp_starts(source, target, o);
  const int num_starts = static_cast<int>(result.start_transforms.size());
  std::vector<Track> tracks(static_cast<size_t>(num_starts));
  for (int k = 0; k < num_starts; ++k) {
    tracks[k].T = result.start_transforms[k];
    tracks[k].determinant = tracks[k].T.is_reflection() ? -1 : 1;
  }

  CSHAPES_REQUIRE(source.pyramid() == o.pyramid && target.pyramid() == o.pyramid && source.seed() == o.seed &&
                      target.seed() == o.seed,
                  "ICP: both shapes must be built with the options' pyramid and seed");
  const int levels = source.num_levels();

  // Screening: every start, a few steps on the coarsest level.
  for_each_start(num_starts, o.parallel, [&](int k) {
    iterate(tracks[static_cast<size_t>(k)], source, target, 0, o.screening_iterations, o);
  });
  result.start_rmse.resize(static_cast<size_t>(num_starts));
  for (int k = 0; k < num_starts; ++k)
    result.start_rmse[static_cast<size_t>(k)] = tracks[static_cast<size_t>(k)].rmse;

  std::vector<int> order(static_cast<size_t>(num_starts));
  std::iota(order.begin(), order.end(), 0);
  auto by_rmse = [&](int a, int b) {
    double ra = tracks[static_cast<size_t>(a)].rmse, rb = tracks[static_cast<size_t>(b)].rmse;
    return ra < rb || (ra == rb && a < b);
  };
  std::stable_sort(order.begin(), order.end(), by_rmse);
  order.resize(static_cast<size_t>(std::min(num_starts, o.finalists)));

  // The finalists to convergence on each subsampled level, re-ranked after each.
  for (int level = 0; level + 1 < levels; ++level) {
    for_each_start(static_cast<int>(order.size()), o.parallel, [&](int f) {
      iterate(tracks[static_cast<size_t>(order[static_cast<size_t>(f)])], source, target, level,
              o.max_iterations, o);
    });
    std::stable_sort(order.begin(), order.end(), by_rmse);
  }
  // The best one to convergence on all points.
  const int best = order.front();
  Track& winner = tracks[static_cast<size_t>(best)];
  const bool refined = o.refine_on_all_points || levels == 1;
  if (refined) iterate(winner, source, target, levels - 1, o.max_iterations, o);

  // Back from centred coordinates: y − c_t = R (x − c_s) + t'  ⇒  t = t' + c_t − R c_s.
  result.transform.rotation = winner.T.rotation;
  result.transform.translation =
      winner.T.translation + target.centroid() - winner.T.rotation * source.centroid();
  result.rmse = winner.rmse;
  result.inlier_fraction = winner.inlier_fraction;
  result.iterations = winner.iterations;
  result.converged = winner.converged;
  result.stop_reason = winner.stop_reason;
  result.best_start = best;
  result.rmse_history = winner.history;
  for (const Track& t : tracks) result.total_iterations += t.total_iterations;

  // Nearest neighbours under the final transform, on all points, both directions: those of the last pass
  // when it saw the final transform, else one more pass.
  const int full = levels - 1;
  const Points& S = source.level_points(full);
  const Points& Tg = target.level_points(full);
  if (!winner.current || winner.nn_st.size() != S.rows()) {
    target.tree().nearest_all(winner.T.apply(S), winner.nn_st, winner.d2_st);
  }
  if (!winner.current || winner.nn_ts.size() != Tg.rows()) {
    source.tree().nearest_all(winner.T.inverse().apply(Tg), winner.nn_ts, winner.d2_ts);
  }
  // Level rows back to the input's rows.
  const std::vector<int>& source_rows = source.level_indices(full);
  const std::vector<int>& target_rows = target.level_indices(full);
  result.source_to_target.resize(S.rows());
  result.source_to_target_distance.resize(S.rows());
  for (Index k = 0; k < S.rows(); ++k) {
    result.source_to_target[source_rows[static_cast<size_t>(k)]] =
        target_rows[static_cast<size_t>(winner.nn_st[k])];
    result.source_to_target_distance[source_rows[static_cast<size_t>(k)]] = std::sqrt(winner.d2_st[k]);
  }
  result.target_to_source.resize(Tg.rows());
  result.target_to_source_distance.resize(Tg.rows());
  for (Index k = 0; k < Tg.rows(); ++k) {
    result.target_to_source[target_rows[static_cast<size_t>(k)]] =
        source_rows[static_cast<size_t>(winner.nn_ts[k])];
    result.target_to_source_distance[target_rows[static_cast<size_t>(k)]] = std::sqrt(winner.d2_ts[k]);
  }
  if (!refined) {  // the RMSE of all pairs under the subsample's transform
    result.rmse =
        std::sqrt((winner.d2_st.sum() + winner.d2_ts.sum()) / static_cast<double>(S.rows() + Tg.rows()));
    result.inlier_fraction = 1;
    result.iterations = 0;
  }
  result.seconds = seconds_since(clock_start);
  return result;
}

IcpResult icp(const Points& source, const Points& target, const IcpOptions& options) {
  IcpShape s(source, options), t(target, options);
  return icp(s, t, options);
}

std::string to_key_string(const IcpOptions& o) {
  return "icp;" + options_key(o);
}

}  // namespace cshapes
