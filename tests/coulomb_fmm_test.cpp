#include "cshapes/canon/coulomb_fmm.h"

#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "cshapes/data/synthetic.h"
#include "cshapes/mesh/io.h"
#include "tests/test_support.h"

namespace cshapes {
namespace coulomb_fmm_test {

// The bench's distributions (data/synthetic.h random_points): uniform cube, unit sphere surface, 20
// Gaussian clusters of widths 1e-3 … 1e-1.
Points make_points(Index n, const std::string& distribution, unsigned seed) {
  std::mt19937_64 rng(seed);
  return random_points(n, parse_point_distribution(distribution), rng);
}

// Relative L2 gradient error and relative energy error against exact direct summation (the bench's measure,
// canon/coulomb_energy.h coulomb_errors): complete when `sample` is 0, else on `sample` random targets
// (energy error then from their potentials).
CoulombErrors fmm_errors(const Points& X, const CoulombFmmOptions& options, Index sample = 0) {
  CoulombFmmOptions o = options;
  o.want_potentials = true;
  const CoulombEvaluation fast = coulomb_fmm(X, o);
  if (sample == 0) return coulomb_errors(fast, coulomb_direct(X));
  std::mt19937_64 rng(99);
  std::vector<Index> targets(sample);
  for (Index& t : targets) t = std::uniform_int_distribution<Index>(0, X.rows() - 1)(rng);
  return coulomb_errors(fast, targets, coulomb_direct_targets(X, targets));
}

TEST(CoulombFmm, DefaultAccuracyContractOnSmallSets) {
  for (const char* distribution : {"uniform", "sphere", "clustered"}) {
    const CoulombErrors e = fmm_errors(make_points(2000, distribution, 1), {});
    EXPECT_LE(e.gradient, 1e-3) << distribution;
    EXPECT_LE(e.energy, 1e-4) << distribution;
  }
}

TEST(CoulombFmm, DefaultAccuracyContractOnLargerSets) {
  for (const char* distribution : {"uniform", "sphere", "clustered"}) {
    const CoulombErrors e = fmm_errors(make_points(20000, distribution, 2), {}, 400);
    EXPECT_LE(e.gradient, 1e-3) << distribution;
    EXPECT_LE(e.energy, 1e-4) << distribution;
  }
}

TEST(CoulombFmm, DefaultAccuracyContractOnTosca) {
  CSHAPES_REQUIRE_DATA();
  for (const char* name : {"cat0", "michael0"}) {
    const Mesh mesh = read_mesh(test::tosca5k(name));
    const CoulombErrors e = fmm_errors(mesh.V, {});
    EXPECT_LE(e.gradient, 1e-3) << name;
    EXPECT_LE(e.energy, 1e-4) << name;
  }
}

// Regular spacing and a cancelling gradient (the hard case for the error, as on TOSCA), at several sizes, and
// points sampled on a torus-like surface: the default contract holds everywhere.
TEST(CoulombFmm, DefaultAccuracyContractOnGeneratedMeshesOfSeveralSizes) {
  for (const auto& [nu, nv] : {std::pair{60, 20}, std::pair{140, 45}, std::pair{300, 100}}) {
    const Mesh mesh = torus(nu, nv);
    const CoulombErrors e = fmm_errors(mesh.V, {}, mesh.V.rows() > 10000 ? 1000 : 0);
    EXPECT_LE(e.gradient, 1e-3) << "torus " << nu << "x" << nv;
    EXPECT_LE(e.energy, 1e-4) << "torus " << nu << "x" << nv;
  }
  for (int subdivisions : {4, 5}) {
    const Mesh mesh = icosphere(subdivisions);
    const CoulombErrors e = fmm_errors(mesh.V, {});
    EXPECT_LE(e.gradient, 1e-3) << "icosphere " << subdivisions;
    EXPECT_LE(e.energy, 1e-4) << "icosphere " << subdivisions;
  }
}

// The near field in local frames (at 3e-4, with the Newton step) against the exact-difference near field
// (chosen for accuracy < 3e-4) with the same expansions: they differ only by the rounding of the point
// differences, which must stay far below the accuracy even for nearly coincident pairs. At 1e-3 (the default)
// the frames take the 12-bit estimate of 1/r as it is: further off, still 10× inside the accuracy here.
TEST(CoulombFmm, FramedNearFieldAgreesWithExactDifferences) {
  Points X = make_points(20000, "clustered", 7);
  std::mt19937_64 rng(8);
  std::uniform_real_distribution<double> offset(-1e-6, 1e-6);
  for (Index i = 0; i < 200; ++i)
    X.row(2 * i + 1) = X.row(2 * i) + Eigen::RowVector3d(offset(rng), offset(rng), offset(rng));
  X.row(401) = X.row(400);  // coincident: the distance floor, finite
  CoulombFmmOptions framed;
  framed.accuracy = 3e-4;
  framed.order = 4, framed.opening_angle = 0.45, framed.leaf_size = 48;
  CoulombFmmOptions exact = framed, unrefined = framed;
  exact.accuracy = 1e-5;
  unrefined.accuracy = 1e-3;
  const CoulombEvaluation a = coulomb_fmm(X, framed), b = coulomb_fmm(X, exact),
                          c = coulomb_fmm(X, unrefined);
  ASSERT_TRUE(a.gradient.allFinite());
  ASSERT_TRUE(c.gradient.allFinite());
  EXPECT_LE((a.gradient - b.gradient).norm() / b.gradient.norm(), 1e-5);
  EXPECT_LE(std::abs(a.energy - b.energy) / b.energy, 1e-6);
  EXPECT_LE((c.gradient - b.gradient).norm() / b.gradient.norm(), 1e-4);
  EXPECT_LE(std::abs(c.energy - b.energy) / b.energy, 1e-4);
  EXPECT_GT((c.gradient - b.gradient).norm(), (a.gradient - b.gradient).norm());  // the step is skipped
}

TEST(CoulombFmm, AccuracyParameterIsHonoured) {
  for (double accuracy : {1e-2, 1e-4, 3e-6}) {
    for (const char* distribution : {"uniform", "sphere"}) {
      CoulombFmmOptions o;
      o.accuracy = accuracy;
      const CoulombErrors e = fmm_errors(make_points(3000, distribution, 3), o);
      EXPECT_LE(e.gradient, accuracy) << distribution << " accuracy " << accuracy;
      EXPECT_LE(e.energy, accuracy) << distribution << " accuracy " << accuracy;
    }
  }
}

TEST(CoulombFmm, ErrorFallsWithOrder) {
  const Points X = make_points(3000, "sphere", 4);
  double previous = 1;
  for (int order : {1, 2, 4, 6, 8}) {
    CoulombFmmOptions o;
    o.order = order;
    o.opening_angle = 0.5;
    o.leaf_size = 16;
    const double error = fmm_errors(X, o).gradient;
    EXPECT_LT(error, 0.7 * previous) << "order " << order;
    previous = error;
  }
  EXPECT_LT(previous, 1e-5);
}

TEST(CoulombFmm, ReportsWhatItDid) {
  const Points X = make_points(5000, "uniform", 5);
  CoulombFmmStats stats;
  CoulombFmmOptions o;
  o.leaf_size = 32;
  coulomb_fmm(X, o, &stats);
  EXPECT_EQ(stats.leaf_size, 32);
  EXPECT_GT(stats.order, 0);
  EXPECT_GT(stats.leaves, 5000 / 32);
  EXPECT_GT(stats.cells, stats.leaves);
  EXPECT_GT(stats.m2l_interactions, 0);
  // Direct pairs are a small part of all n² pairs, yet at least every point's own leaf.
  EXPECT_LT(stats.p2p_interactions, 5000 * 5000 / 4);
  EXPECT_GE(stats.p2p_interactions, 5000);
}

// A thread keeps its interaction lists' storage from one evaluation to the next: evaluations of other point
// sets in between (other sizes, other accuracies, so other trees and orders) leave no trace in the result.
TEST(CoulombFmm, AnEvaluationIsTheSameAfterOthersOnTheSameThread) {
  const Points X = make_points(6000, "clustered", 3);
  CoulombFmmOptions options;
  options.accuracy = 1e-2;
  const CoulombEvaluation first = coulomb_fmm(X, options);
  for (const auto& [n, accuracy] : {std::pair<Index, double>{20000, 1e-3}, {500, 1e-2}, {6000, 1e-4}}) {
    CoulombFmmOptions other;
    other.accuracy = accuracy;
    coulomb_fmm(make_points(n, "uniform", 4), other);
  }
  const CoulombEvaluation again = coulomb_fmm(X, options);
  EXPECT_EQ(first.energy, again.energy);
  EXPECT_TRUE(first.gradient == again.gradient);
}

TEST(CoulombFmm, RejectsBadOptions) {
  const Points X = make_points(100, "uniform", 6);
  CoulombFmmOptions o;
  o.opening_angle = 1.5;
  EXPECT_THROW(coulomb_fmm(X, o), std::exception);
  o = {};
  o.accuracy = 0;
  EXPECT_THROW(coulomb_fmm(X, o), std::exception);
}

}  // namespace coulomb_fmm_test
}  // namespace cshapes
