#include "cshapes/canon/metric_projection.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <omp.h>
#include <random>

#include "cshapes/support/error.h"
#include "cshapes/mesh/mesh.h"
#include "cshapes/data/synthetic.h"

namespace cshapes {
namespace metric_projection_test {

Points perturbed(const Points& V, double sigma, unsigned seed) {
  std::mt19937 rng(seed);
  std::normal_distribution<double> noise(0, sigma);
  Points X = V;
  for (Index i = 0; i < X.rows(); ++i)
    for (int c = 0; c < 3; ++c) X(i, c) += noise(rng);
  return X;
}

double mean_edge(const Points& V, const Edges& E) { return edge_lengths(V, E).mean(); }

TEST(MetricProjection, UnperturbedMeshIsAFixedPoint) {
  for (const Mesh& m : {icosphere(3), torus(30, 12), swiss_roll()}) {
    const Edges E = mesh_edges(m.F);
    const double h = mean_edge(m.V, E);
    for (ProjectionNorm norm : {ProjectionNorm::L2, ProjectionNorm::L1}) {
      MetricProjectionOptions o;
      o.norm = norm;
      o.steps = 5;
      MetricProjection P(m.num_vertices(), E, edge_lengths(m.V, E), o);
      Points X = m.V;
      P.project(X);
      EXPECT_LT((X - m.V).cwiseAbs().maxCoeff(), 1e-12 * h) << to_string(norm);
    }
  }
}

TEST(MetricProjection, DilationBandLeavesLengthsInsideItAlone) {
  const Mesh m = icosphere(3);
  const Edges E = mesh_edges(m.F);
  MetricProjectionOptions o;
  o.dilation = 1.2;
  MetricProjection P(m.num_vertices(), E, edge_lengths(m.V, E), o);
  Points X = m.V * 1.1;  // every edge 10% longer: inside [d/1.2, 1.2 d]
  const Points before = X;
  P.project(X);
  EXPECT_LT((X - before).cwiseAbs().maxCoeff(), 1e-12);
  // Outside the band, a sweep never increases the squared distance of the lengths to the band: it alternates
  // an L2 sweep towards the nearest band points with re-choosing them.
  const Eigen::VectorXd rest = edge_lengths(m.V, E);
  auto band_residual = [&](const Points& Y) {
    double sum = 0;
    for (Index e = 0; e < E.rows(); ++e) {
      const double r = (Y.row(E(e, 0)) - Y.row(E(e, 1))).norm();
      const double gap = r - std::clamp(r, rest(e) / 1.2, rest(e) * 1.2);
      sum += gap * gap;
    }
    return sum;
  };
  X = perturbed(m.V, 0.5 * rest.mean(), 5);
  double residual = band_residual(X);
  const double initial = residual;
  for (int s = 0; s < 20; ++s) {
    P.sweep(X);
    const double next = band_residual(X);
    EXPECT_LE(next, residual * (1 + 1e-12)) << "sweep " << s;
    residual = next;
  }
  EXPECT_LT(residual, 0.5 * initial);
}

TEST(MetricProjection, L2SweepNeverIncreasesTheResidualOfEq5) {
  for (const Mesh& m : {icosphere(3), torus(30, 12), swiss_roll()}) {
    const Edges E = mesh_edges(m.F);
    const Eigen::VectorXd rest = edge_lengths(m.V, E);
    const double h = rest.mean();
    MetricProjection P(m.num_vertices(), E, rest);
    for (double sigma : {0.05, 0.3, 1.0}) {
      Points X = perturbed(m.V, sigma * h, 11);
      double residual = metric_violation(X, E, rest).residual;
      const double initial = residual;
      for (int s = 0; s < 20; ++s) {
        P.sweep(X);
        const double next = metric_violation(X, E, rest).residual;
        EXPECT_LE(next, residual * (1 + 1e-12)) << "sweep " << s << ", sigma " << sigma;
        residual = next;
      }
      EXPECT_LT(residual, 0.9 * initial);
    }
  }
}

TEST(MetricProjection, ScaleInvariant) {
  const Mesh m = icosphere(2);
  const Edges E = mesh_edges(m.F);
  for (ProjectionNorm norm : {ProjectionNorm::L2, ProjectionNorm::L1}) {
    MetricProjectionOptions o;
    o.norm = norm;
    Points X = perturbed(m.V, 0.05, 3);
    Points big = X * 1e6;
    MetricProjection(m.num_vertices(), E, edge_lengths(m.V, E), o).project(X);
    MetricProjection(m.num_vertices(), E, edge_lengths(m.V * 1e6, E), o).project(big);
    EXPECT_LT((big / 1e6 - X).cwiseAbs().maxCoeff(), 1e-9);
  }
}

TEST(MetricProjection, L1GivesWayAtAStronglyStretchedEdge) {
  // A glued bridge: one extra edge whose rest length is far shorter than the distance it spans.
  const Mesh m = grid(12, 12, 11.0, 11.0);
  Edges E = mesh_edges(m.F);
  Eigen::VectorXd rest = edge_lengths(m.V, E);
  const Index a = 0, b = 11;  // opposite corners of one side, 11 apart
  E.conservativeResize(E.rows() + 1, 2);
  E.row(E.rows() - 1) << a, b;
  rest.conservativeResize(rest.size() + 1);
  rest(rest.size() - 1) = 1.0;
  auto pulled = [&](ProjectionNorm norm) {
    MetricProjectionOptions o;
    o.norm = norm;
    o.steps = 50;
    Points X = m.V;
    MetricProjection(m.num_vertices(), E, rest, o).project(X);
    return (X.row(a) - X.row(b)).norm();
  };
  // The L1 weights shrink the bridge's pull, so the corners stay further apart than with L2.
  EXPECT_GT(pulled(ProjectionNorm::L1), pulled(ProjectionNorm::L2) + 0.5);
}

TEST(MetricProjection, CoincidentEndpointsGiveFiniteResults) {
  const Mesh m = icosphere(2);
  const Edges E = mesh_edges(m.F);
  Points X = m.V;
  X.row(E(0, 1)) = X.row(E(0, 0));
  X.row(E(5, 1)) = X.row(E(5, 0));
  for (ProjectionNorm norm : {ProjectionNorm::L2, ProjectionNorm::L1}) {
    MetricProjectionOptions o;
    o.norm = norm;
    MetricProjection P(m.num_vertices(), E, edge_lengths(m.V, E), o);
    Points Y = X;
    P.project(Y);
    EXPECT_TRUE(Y.allFinite());
    EXPECT_GT((Y.row(E(0, 1)) - Y.row(E(0, 0))).norm(), 0);
  }
}

// One sweep of eq. (6) / eq. (8)-(9) / eq. (3) evaluated literally, vertex by vertex over the adjacency: the
// reference for the two-pass, vectorised sweep.
Points reference_sweep(const Points& X, const Edges& E, const Eigen::VectorXd& rest, const MetricProjectionOptions& o) {
  const Adjacency adj = adjacency(X.rows(), E);
  Points out = X;
  for (Index i = 0; i < X.rows(); ++i) {
    Eigen::RowVector3d sum = Eigen::RowVector3d::Zero();
    double weight_sum = 0;
    for (int k = adj.offsets[i]; k < adj.offsets[i + 1]; ++k) {
      const int j = adj.neighbors[k];
      const double d = rest(adj.edge_ids[k]);
      const Eigen::RowVector3d u = X.row(i) - X.row(j);
      const double r = u.norm();
      const double t = std::clamp(r, d / o.dilation, d * o.dilation);
      const double w = o.norm == ProjectionNorm::L1 ? 1.0 / std::max(std::abs(r - d), o.l1_floor * d) : 1.0;
      Eigen::RowVector3d p = X.row(j) + (t / r) * u;
      if (r <= 1e-12 * d) p = X.row(j) + Eigen::RowVector3d(i < j ? t : -t, 0, 0);
      sum += w * p;
      weight_sum += w;
    }
    if (weight_sum > 0) out.row(i) = sum / weight_sum;
  }
  return out;
}

TEST(MetricProjection, SweepMatchesTheLiteralFormula) {
  const Mesh m = torus(40, 15);
  const Edges E = mesh_edges(m.F);
  const Eigen::VectorXd rest = edge_lengths(m.V, E);
  const double h = rest.mean();
  Points X = perturbed(m.V * 1.2, 0.3 * h, 11);
  X.row(E(3, 1)) = X.row(E(3, 0));  // one pair of coincident endpoints
  for (ProjectionNorm norm : {ProjectionNorm::L2, ProjectionNorm::L1})
    for (double dilation : {1.0, 1.1}) {
      MetricProjectionOptions o;
      o.norm = norm;
      o.dilation = dilation;
      Points Y = X;
      MetricProjection(m.num_vertices(), E, rest, o).sweep(Y);
      EXPECT_LT((Y - reference_sweep(X, E, rest, o)).cwiseAbs().maxCoeff(), 1e-12 * h)
          << to_string(norm) << ", dilation " << dilation;
    }
}

TEST(MetricProjection, EdgeOrderAndOrientationDoNotMatter) {
  const Mesh m = icosphere(3);
  const Edges E = mesh_edges(m.F);
  const Eigen::VectorXd rest = edge_lengths(m.V, E);
  // The same graph, edges reversed and listed backwards.
  Edges F(E.rows(), 2);
  Eigen::VectorXd rest_f(E.rows());
  for (Index e = 0; e < E.rows(); ++e) {
    F.row(E.rows() - 1 - e) << E(e, 1), E(e, 0);
    rest_f(E.rows() - 1 - e) = rest(e);
  }
  const Points X0 = perturbed(m.V, 0.05, 5);
  Points A = X0, B = X0;
  MetricProjection(m.num_vertices(), E, rest).project(A);
  MetricProjection(m.num_vertices(), F, rest_f).project(B);
  EXPECT_TRUE(A == B);
}

TEST(MetricProjection, IdenticalResultsOnAnyNumberOfThreads) {
  // Large enough for the parallel path (icosphere(5): 10,242 vertices).
  const Mesh m = icosphere(5);
  const Edges E = mesh_edges(m.F);
  const Eigen::VectorXd rest = edge_lengths(m.V, E);
  const Points X0 = perturbed(m.V * 1.1, 0.01, 9);
  const int threads = omp_get_max_threads();
  for (ProjectionNorm norm : {ProjectionNorm::L2, ProjectionNorm::L1}) {
    MetricProjectionOptions o;
    o.norm = norm;
    const MetricProjection P(m.num_vertices(), E, rest, o);
    Points A = X0, B = X0;
    omp_set_num_threads(1);
    P.project(A);
    const RelativeViolation va = P.relative_violation(A);
    omp_set_num_threads(std::max(2, threads));
    P.project(B);
    const RelativeViolation vb = P.relative_violation(B);
    omp_set_num_threads(threads);
    EXPECT_TRUE(A == B) << to_string(norm);
    EXPECT_EQ(va.mean, vb.mean);
    EXPECT_EQ(va.max, vb.max);
  }
}

TEST(MetricProjection, RelativeViolationMatchesMetricViolation) {
  const Mesh m = torus(30, 12);
  const Edges E = mesh_edges(m.F);
  const Eigen::VectorXd rest = edge_lengths(m.V, E);
  const Points X = perturbed(m.V, 0.05, 4);
  const MetricViolation full = metric_violation(X, E, rest);
  const RelativeViolation v = MetricProjection(m.num_vertices(), E, rest).relative_violation(X);
  EXPECT_NEAR(v.mean, full.mean_relative, 1e-12 * full.mean_relative);
  EXPECT_EQ(v.max, full.max_relative);
  EXPECT_LT(MetricProjection(m.num_vertices(), E, rest).relative_violation(m.V).max, 1e-14);
}

TEST(MetricViolation, KnownAnswers) {
  Points X(3, 3);
  X << 0, 0, 0, 2, 0, 0, 2, 3, 0;
  Edges E(2, 2);
  E << 0, 1, 1, 2;
  Eigen::VectorXd rest(2);
  rest << 1, 3;
  const MetricViolation v = metric_violation(X, E, rest);
  EXPECT_DOUBLE_EQ(v.residual, 1.0);
  EXPECT_DOUBLE_EQ(v.l1, 1.0);
  EXPECT_DOUBLE_EQ(v.mean_relative, 0.5);
  EXPECT_DOUBLE_EQ(v.max_relative, 1.0);
}

TEST(MetricProjection, RejectsBadInput) {
  Edges E(1, 2);
  E << 0, 3;
  EXPECT_THROW(MetricProjection(3, E, Eigen::VectorXd::Ones(1)), Error);
  E << 0, 1;
  EXPECT_THROW(MetricProjection(3, E, Eigen::VectorXd::Ones(2)), Error);
  MetricProjectionOptions o;
  o.dilation = 0.5;
  EXPECT_THROW(MetricProjection(3, E, Eigen::VectorXd::Ones(1), o), Error);
}

}  // namespace metric_projection_test
}  // namespace cshapes
