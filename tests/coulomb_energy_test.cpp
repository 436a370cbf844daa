#include "cshapes/canon/coulomb_energy.h"

#include <gtest/gtest.h>
#include <omp.h>

#include <cmath>
#include <random>

#include "cshapes/data/synthetic.h"

namespace cshapes {
namespace coulomb_energy_test {

using Summation = CoulombOptions::Summation;

Points random_points(Index n, unsigned seed, double scale = 1.0) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> u(-scale, scale);
  Points X(n, 3);
  for (Index i = 0; i < n; ++i) X.row(i) << u(rng), u(rng), u(rng);
  return X;
}

CoulombEvaluation evaluate(const Points& X, Summation summation) {
  CoulombOptions o;
  o.summation = summation;
  return coulomb_energy_gradient(X, o);
}

// Every summation, the fast one at 1e-5 (its near field's 1/r refined to about 23 bits) and at its default
// 1e-3 (the hardware's 12-bit estimate as it is: within the accuracy asked, not to 1e-6).
TEST(CoulombEnergy, TwoPointsKnownAnswer) {
  Points X(2, 3);
  X << 0, 0, 0, 3, 4, 0;  // distance 5
  for (double tolerance : {1e-6, 1e-3}) {
    for (Summation s : {Summation::Direct, Summation::DirectFloat, Summation::Fast}) {
      if (tolerance > 1e-6 && s != Summation::Fast) continue;
      CoulombOptions o;
      o.summation = s;
      if (tolerance == 1e-6) o.accuracy = 1e-5;
      const CoulombEvaluation e = coulomb_energy_gradient(X, o);
      EXPECT_NEAR(e.energy, 2.0 / 5, tolerance * 2.0 / 5);  // ordered pairs: 1/5 twice
      // ∇_0 E = −2 (x_0 − x_1)/r³
      const double g = tolerance * 2.0 / 25;  // the tolerance relative to |∇_0 E| = 2/25
      EXPECT_NEAR(e.gradient(0, 0), -2 * -3.0 / 125, g);
      EXPECT_NEAR(e.gradient(0, 1), -2 * -4.0 / 125, g);
      EXPECT_NEAR(e.gradient(1, 0), 2 * -3.0 / 125, g);
      EXPECT_NEAR(e.gradient(0, 2), 0, 1e-12);
    }
  }
}

TEST(CoulombEnergy, GradientMatchesCentralFiniteDifferences) {
  const Points X = random_points(40, 7);
  const CoulombEvaluation e = coulomb_direct(X);
  const double scale = e.gradient.cwiseAbs().maxCoeff();
  const double h = 1e-5;
  for (Index i : {0, 13, 39})
    for (int c = 0; c < 3; ++c) {
      Points plus = X, minus = X;
      plus(i, c) += h, minus(i, c) -= h;
      const double fd = (coulomb_direct(plus).energy - coulomb_direct(minus).energy) / (2 * h);
      EXPECT_NEAR(e.gradient(i, c), fd, 1e-6 * scale) << "point " << i << " coordinate " << c;
    }
}

TEST(CoulombEnergy, PotentialsSumToEnergy) {
  const Points X = random_points(300, 3);
  const CoulombEvaluation e = coulomb_direct(X);
  EXPECT_NEAR(e.potential.sum(), e.energy, 1e-12 * e.energy);
  CoulombOptions o;
  o.summation = Summation::Fast;
  o.want_potentials = true;
  const CoulombEvaluation f = coulomb_energy_gradient(X, o);
  ASSERT_EQ(f.potential.size(), 300);
  EXPECT_NEAR(f.potential.sum(), f.energy, 1e-12 * f.energy);
}

TEST(CoulombEnergy, FloatDirectMatchesDoubleDirect) {
  const Points X = random_points(3000, 11);
  const CoulombEvaluation d = coulomb_direct(X);
  const CoulombEvaluation f = coulomb_direct_float(X, 0, true);
  EXPECT_LT(relative_l2_error(f.gradient, d.gradient), 1e-5);
  EXPECT_NEAR(f.energy, d.energy, 1e-6 * d.energy);
  EXPECT_LT((f.potential - d.potential).norm() / d.potential.norm(), 1e-6);
}

TEST(CoulombEnergy, DirectOnTargetsMatchesFullDirect) {
  const Points X = random_points(500, 5);
  const CoulombEvaluation d = coulomb_direct(X);
  const std::vector<Index> targets = {499, 0, 17, 17, 250};
  const CoulombTargetSums t = coulomb_direct_targets(X, targets);
  for (size_t k = 0; k < targets.size(); ++k) {
    EXPECT_DOUBLE_EQ(t.potential[k], d.potential[targets[k]]);
    for (int c = 0; c < 3; ++c) EXPECT_DOUBLE_EQ(t.gradient(k, c), d.gradient(targets[k], c));
  }
  EXPECT_THROW(coulomb_direct_targets(X, {500}), std::exception);
}

// The error measure itself: known answers for a perturbed evaluation, and the sampled form equal to the
// complete one when every point is a target.
TEST(CoulombErrors, KnownAnswersFullAndSampled) {
  const Points X = random_points(300, 11);
  const CoulombEvaluation d = coulomb_direct(X);
  EXPECT_EQ(coulomb_errors(d, d).gradient, 0.0);
  EXPECT_EQ(coulomb_errors(d, d).energy, 0.0);
  CoulombEvaluation off = d;
  off.gradient *= 1.001;  // every row 0.1% long: relative L2 error 1e-3
  off.energy *= 0.99;
  off.potential *= 0.99;
  const CoulombErrors full = coulomb_errors(off, d);
  EXPECT_NEAR(full.gradient, 1e-3, 1e-12);
  EXPECT_NEAR(full.energy, 1e-2, 1e-12);
  std::vector<Index> all(300);
  for (Index i = 0; i < 300; ++i) all[i] = 299 - i;
  const CoulombErrors sampled = coulomb_errors(off, all, coulomb_direct_targets(X, all));
  EXPECT_NEAR(sampled.gradient, full.gradient, 1e-12);
  EXPECT_NEAR(sampled.energy, full.energy, 1e-12);
  // One wrong row among the sampled targets shows; a wrong row outside them does not.
  CoulombEvaluation one = d;
  one.gradient.row(5) *= 2;
  const std::vector<Index> with5 = {5, 6, 7}, without5 = {6, 7, 8};
  EXPECT_GT(coulomb_errors(one, with5, coulomb_direct_targets(X, with5)).gradient, 0.1);
  EXPECT_EQ(coulomb_errors(one, without5, coulomb_direct_targets(X, without5)).gradient, 0.0);
  EXPECT_NEAR(relative_l2_error(off.gradient, d.gradient), 1e-3, 1e-12);
  CoulombEvaluation no_potentials = d;
  no_potentials.potential.resize(0);
  EXPECT_THROW(coulomb_errors(no_potentials, with5, coulomb_direct_targets(X, with5)), std::exception);
}

// Coincident points: finite everywhere, no mutual force, each adds 1/min_distance to the other's potential.
TEST(CoulombEnergy, CoincidentPointsGiveFiniteResults) {
  Points X = random_points(400, 9);
  for (Index i = 0; i < 150; ++i) X.row(200 + i) = X.row(0);  // 151 copies of one point (more than a leaf)
  X.row(399) = X.row(1);
  const double floor = 1e-3;
  CoulombEvaluation reference = coulomb_direct(X, floor);
  ASSERT_TRUE(reference.gradient.allFinite());
  ASSERT_TRUE(std::isfinite(reference.energy));
  for (Summation s : {Summation::Direct, Summation::DirectFloat, Summation::Fast}) {
    CoulombOptions o;
    o.summation = s;
    o.min_distance = floor;
    // 151 charges at one spot weigh the error of their neighbours outside the default accuracy contract
    // (made for distinct points); a tighter accuracy still brings the error below 1e-3.
    o.accuracy = 1e-5;
    const CoulombEvaluation e = coulomb_energy_gradient(X, o);
    EXPECT_TRUE(e.gradient.allFinite()) << int(s);
    EXPECT_TRUE(std::isfinite(e.energy)) << int(s);
    EXPECT_NEAR(e.energy, reference.energy, 1e-4 * reference.energy) << int(s);
    EXPECT_LT(relative_l2_error(e.gradient, reference.gradient), 1e-3) << int(s);
  }
  // Points 1 and 399 coincide: the same gradient (they see the same other points and not each other).
  EXPECT_NEAR((reference.gradient.row(1) - reference.gradient.row(399)).norm(), 0,
              1e-12 * reference.gradient.row(1).norm());
  // The pair contributes 2 · 1/floor to the energy: removing point 399 changes E by 2(1/floor + Σ others).
  Points without = X.topRows(399);
  const double others = reference.potential[399] - 1 / floor;
  EXPECT_NEAR(reference.energy - coulomb_direct(without, floor).energy, 2 * (1 / floor + others),
              1e-9 * reference.energy);
  // The default floor: all points coincident still gives zeros, not NaN.
  Points same = Points::Ones(50, 3);
  for (Summation s : {Summation::Direct, Summation::DirectFloat, Summation::Fast}) {
    const CoulombEvaluation e = evaluate(same, s);
    EXPECT_TRUE(e.gradient.allFinite() && std::isfinite(e.energy)) << int(s);
    EXPECT_EQ(e.gradient.cwiseAbs().maxCoeff(), 0.0) << int(s);
  }
}

TEST(CoulombEnergy, TranslationInvariantRotationEquivariant) {
  const Points X = random_points(2500, 21);
  const Eigen::Matrix3d Rot =
      Eigen::AngleAxisd(0.7, Eigen::Vector3d(1, 2, 3).normalized()).toRotationMatrix();
  const Eigen::RowVector3d shift(10, -4, 2.5);
  const Points moved = (X * Rot.transpose()).rowwise() + shift;
  for (Summation s : {Summation::Direct, Summation::DirectFloat, Summation::Fast}) {
    const CoulombEvaluation a = evaluate(X, s), b = evaluate(moved, s);
    const double tolerance = s == Summation::Fast ? 1e-3 : 1e-5;
    EXPECT_NEAR(b.energy, a.energy, tolerance * 0.1 * a.energy) << int(s);
    EXPECT_LT(relative_l2_error(b.gradient, a.gradient * Rot.transpose()), tolerance) << int(s);
  }
}

TEST(CoulombEnergy, ScalesAsInverseDistance) {
  const Points X = random_points(1000, 4);
  for (Summation s : {Summation::Direct, Summation::DirectFloat, Summation::Fast}) {
    const CoulombEvaluation a = evaluate(X, s);
    for (double scale : {1e-8, 1e8}) {
      const CoulombEvaluation b = evaluate(X * scale, s);
      EXPECT_NEAR(b.energy * scale, a.energy, 1e-5 * a.energy) << int(s) << " scale " << scale;
      EXPECT_LT(relative_l2_error(b.gradient * scale * scale, a.gradient), 1e-5)
          << int(s) << " scale " << scale;
    }
  }
}

TEST(CoulombEnergy, IdenticalOutputsForIdenticalInputsAndAnyThreadCount) {
  const Points X = random_points(6000, 8);
  const int threads = omp_get_max_threads();
  for (Summation s : {Summation::Direct, Summation::DirectFloat, Summation::Fast}) {
    const CoulombEvaluation a = evaluate(X, s), b = evaluate(X, s);
    EXPECT_EQ(a.energy, b.energy);
    EXPECT_TRUE((a.gradient.array() == b.gradient.array()).all()) << int(s);
    omp_set_num_threads(1);
    const CoulombEvaluation c = evaluate(X, s);
    omp_set_num_threads(threads);
    EXPECT_EQ(a.energy, c.energy) << int(s);
    EXPECT_TRUE((a.gradient.array() == c.gradient.array()).all()) << int(s);
  }
}

TEST(CoulombEnergy, AutoPicksBySize) {
  EXPECT_EQ(evaluate(random_points(kAutoFastMinPoints - 1, 1), Summation::Auto).summation_used,
            Summation::DirectFloat);
  EXPECT_EQ(evaluate(random_points(kAutoFastMinPoints, 1), Summation::Auto).summation_used, Summation::Fast);
  EXPECT_EQ(evaluate(random_points(10, 1), Summation::Direct).summation_used, Summation::Direct);
}

TEST(CoulombEnergy, RejectsNonFiniteInput) {
  Points X = random_points(10, 1);
  X(3, 1) = std::nan("");
  EXPECT_THROW(coulomb_energy_gradient(X), std::exception);
}

TEST(CoulombEnergy, SingleAndNoPoint) {
  for (Summation s : {Summation::Direct, Summation::DirectFloat, Summation::Fast}) {
    const CoulombEvaluation one = evaluate(Points::Zero(1, 3), s);
    EXPECT_EQ(one.energy, 0.0);
    EXPECT_EQ(one.gradient.rows(), 1);
    EXPECT_EQ(one.gradient.cwiseAbs().maxCoeff(), 0.0);
    const CoulombEvaluation none = evaluate(Points(0, 3), s);
    EXPECT_EQ(none.energy, 0.0);
    EXPECT_EQ(none.gradient.rows(), 0);
  }
}

}  // namespace coulomb_energy_test
}  // namespace cshapes
