#include "canon/metric_projection.h"

#include <algorithm>
#include <cmath>
#include <vector>

#include "core/error.h"

namespace cshapes {

ProjectionNorm parse_projection_norm(const std::string& name) {
  if (name == "l2") return ProjectionNorm::L2;
  if (name == "l1") return ProjectionNorm::L1;
  fail("unknown projection norm '", name, "'; known: l2, l1");
}

std::string to_string(ProjectionNorm norm) { return norm == ProjectionNorm::L2 ? "l2" : "l1"; }

MetricProjection::MetricProjection(Index num_vertices, const Edges& E, const Eigen::VectorXd& rest_lengths,
                                   const MetricProjectionOptions& options)
    : n_(num_vertices), rest_(rest_lengths), options_(options) {
  CSHAPES_REQUIRE(rest_lengths.size() == E.rows(), "metric projection: ", rest_lengths.size(),
                  " rest lengths for ", E.rows(), " edges");
  CSHAPES_REQUIRE(options.steps >= 0, "metric projection: steps must be >= 0, got ", options.steps);
  CSHAPES_REQUIRE(options.dilation >= 1, "metric projection: dilation must be >= 1, got ", options.dilation);
  CSHAPES_REQUIRE(options.l1_floor > 0, "metric projection: l1_floor must be > 0, got ", options.l1_floor);
  for (Index e = 0; e < E.rows(); ++e) {
    CSHAPES_REQUIRE(E(e, 0) >= 0 && E(e, 0) < n_ && E(e, 1) >= 0 && E(e, 1) < n_ && E(e, 0) != E(e, 1),
                    "metric projection: edge ", e, " (", E(e, 0), ", ", E(e, 1), ") is not a pair of distinct "
                    "vertices in [0, ", n_, ")");
    CSHAPES_REQUIRE(std::isfinite(rest_(e)) && rest_(e) >= 0, "metric projection: rest length of edge ", e,
                    " is ", rest_(e), ", expected a finite value >= 0");
  }
  // Zero rest lengths (duplicate points of a point cloud) are raised to a tiny fraction of the largest, so the
  // relative floors and violations below stay finite.
  const double tiny = 1e-12 * (rest_.size() ? std::max(rest_.maxCoeff(), 1e-300) : 1.0);
  rest_ = rest_.cwiseMax(tiny);
  adj_ = adjacency(n_, E);
  neighbor_rest_.resize(adj_.edge_ids.size());
  for (size_t k = 0; k < adj_.edge_ids.size(); ++k) neighbor_rest_[k] = rest_(adj_.edge_ids[k]);
}

void MetricProjection::sweep(Points& X) const { sweeps(X, 1); }

void MetricProjection::project(Points& X) const { sweeps(X, options_.steps); }

void MetricProjection::sweeps(Points& X, int count) const {
  CSHAPES_REQUIRE(X.rows() == n_, "metric projection: X has ", X.rows(), " rows, expected ", n_);
  if (count <= 0) return;
  buffer_a_.resize(3 * n_);
  buffer_b_.resize(3 * n_);
  for (Index i = 0; i < n_; ++i)
    for (int c = 0; c < 3; ++c) buffer_a_[3 * i + c] = X(i, c);
  const bool l1 = options_.norm == ProjectionNorm::L1;
  const double dilation = options_.dilation, inv_dilation = 1.0 / dilation, floor = options_.l1_floor;
  const int* offsets = adj_.offsets.data();
  const int* neighbors = adj_.neighbors.data();
  const double* rest = neighbor_rest_.data();
  for (int step = 0; step < count; ++step) {
    const double* x = buffer_a_.data();
    double* out = buffer_b_.data();
#pragma omp parallel for schedule(static) if (n_ > 20000)
    for (Index i = 0; i < n_; ++i) {
      const double xi = x[3 * i], yi = x[3 * i + 1], zi = x[3 * i + 2];
      double sx = 0, sy = 0, sz = 0, weight_sum = 0;
      for (int k = offsets[i]; k < offsets[i + 1]; ++k) {
        const int j = neighbors[k];
        const double d = rest[k];
        const double xj = x[3 * j], yj = x[3 * j + 1], zj = x[3 * j + 2];
        const double dx = xi - xj, dy = yi - yj, dz = zi - zj;
        const double r = std::sqrt(dx * dx + dy * dy + dz * dz);
        // eq. (3): the target is the length itself when it lies in the band, so such an edge does not pull.
        const double target = dilation > 1 ? std::clamp(r, d * inv_dilation, d * dilation) : d;
        // eq. (9): weights ~ 1/|r_ij − d_ij|, floored relative to d_ij (see the header).
        const double w = l1 ? 1.0 / std::max(std::abs(r - d), floor * d) : 1.0;
        double px, py, pz;
        if (r > 1e-12 * d) {
          const double scale = target / r;
          px = xj + scale * dx;
          py = yj + scale * dy;
          pz = zj + scale * dz;
        } else {  // coincident endpoints: a fixed direction, opposite for i and j
          px = xj + (i < j ? target : -target);
          py = yj;
          pz = zj;
        }
        sx += w * px;
        sy += w * py;
        sz += w * pz;
        weight_sum += w;
      }
      if (weight_sum > 0) {  // eq. (6) / eq. (8)
        out[3 * i] = sx / weight_sum;
        out[3 * i + 1] = sy / weight_sum;
        out[3 * i + 2] = sz / weight_sum;
      } else {  // an isolated vertex stays where it is
        out[3 * i] = xi;
        out[3 * i + 1] = yi;
        out[3 * i + 2] = zi;
      }
    }
    buffer_a_.swap(buffer_b_);
  }
  for (Index i = 0; i < n_; ++i)
    for (int c = 0; c < 3; ++c) X(i, c) = buffer_a_[3 * i + c];
}

MetricViolation metric_violation(const Points& X, const Edges& E, const Eigen::VectorXd& rest_lengths) {
  CSHAPES_REQUIRE(rest_lengths.size() == E.rows(), "metric violation: ", rest_lengths.size(),
                  " rest lengths for ", E.rows(), " edges");
  MetricViolation v;
  if (E.rows() == 0) return v;
  std::vector<double> ratio(E.rows());
  double sum_relative = 0;
  for (Index e = 0; e < E.rows(); ++e) {
    const double r = (X.row(E(e, 0)) - X.row(E(e, 1))).norm();
    const double d = rest_lengths(e);
    const double dev = std::abs(r - d);
    v.residual += dev * dev;
    v.l1 += dev;
    const double rel = d > 0 ? dev / d : (dev > 0 ? INFINITY : 0.0);
    sum_relative += rel;
    v.max_relative = std::max(v.max_relative, rel);
    ratio[e] = d > 0 ? r / d : 1.0;
  }
  v.mean_relative = sum_relative / E.rows();
  auto mid = ratio.begin() + ratio.size() / 2;
  std::nth_element(ratio.begin(), mid, ratio.end());
  v.median_length_ratio = *mid;
  return v;
}

}  // namespace cshapes
