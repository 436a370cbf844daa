// The fast summation's kept tree (canon/coulomb_fmm.h, CoulombFmmTree): the accuracy contract of a fresh
// tree on points that moved since it was built, the bytes of a fresh tree when it is rebuilt every time, and
// outputs that depend on the inputs only (not on the thread count).
#include <gtest/gtest.h>
#include <omp.h>

#include <cmath>
#include <random>

#include "cshapes/canon/coulomb.h"
#include "cshapes/canon/coulomb_fmm.h"
#include "cshapes/data/synthetic.h"
#include "cshapes/mesh/mesh.h"
#include "cshapes/mesh/rigid_transform.h"
#include "tests/test_support.h"

namespace cshapes {
namespace coulomb_fmm_tree_test {

Points make_points(Index n, const std::string& distribution, unsigned seed) {
  std::mt19937_64 rng(seed);
  return random_points(n, parse_point_distribution(distribution), rng);
}

// The points after `steps` random moves of every point by up to `step` in each coordinate (a Coulomb
// iteration moves a vertex by a fraction of an edge), and a slow drift of the whole set.
std::vector<Points> moving(const Points& X0, int steps, double step, unsigned seed) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> move(-step, step);
  std::vector<Points> sequence{X0};
  for (int s = 1; s < steps; ++s) {
    Points X = sequence.back();
    for (Index i = 0; i < X.rows(); ++i)
      for (int c = 0; c < 3; ++c) X(i, c) += move(rng);
    X.col(0).array() += 0.5 * step;
    sequence.push_back(X);
  }
  return sequence;
}

double mean_spacing(const Points& X) {
  const Eigen::RowVector3d extent = X.colwise().maxCoeff() - X.colwise().minCoeff();
  return std::cbrt(extent.prod() / static_cast<double>(X.rows()));
}

// Every evaluation of a kept tree stays within the accuracy asked, while the tree is kept (and its pairs
// split) as the points move by a tenth of their spacing per step and, in the second case, by several
// spacings per step (a kept tree that no longer fits its points still meets the criterion; it only costs
// more). The clustered points are scaled by 1e12 and the sphere by 1e-12: the tree lives in each evaluation's
// normalized coordinates.
TEST(CoulombFmmTree, KeptTreeMeetsTheAccuracyContractAsPointsMove) {
  struct Case {
    const char* distribution;
    double step_in_spacings, scale;
  };
  for (const auto& [distribution, step_in_spacings, scale] :
       {Case{"clustered", 0.1, 1e12}, Case{"sphere", 0.1, 1e-12}, Case{"uniform", 3.0, 1.0}}) {
    const Points X0 = scale * make_points(4000, distribution, 7);
    const double step = step_in_spacings * mean_spacing(X0);
    for (double accuracy : {1e-2, 1e-3}) {
      CoulombFmmTree tree(100);
      CoulombFmmOptions options;
      options.accuracy = accuracy;
      Index split = 0;
      const std::vector<Points> sequence = moving(X0, 12, step, 8);
      for (size_t s = 0; s < sequence.size(); ++s) {
        CoulombFmmStats stats;
        const CoulombEvaluation fast = coulomb_fmm(sequence[s], options, &stats, &tree);
        EXPECT_EQ(stats.kept_tree, s > 0) << distribution << " step " << s;
        split += stats.pairs_split;
        const CoulombErrors e = coulomb_errors(fast, coulomb_direct(sequence[s]));
        EXPECT_LE(e.gradient, accuracy) << distribution << " accuracy " << accuracy << " step " << s;
      }
      EXPECT_GT(split, 0) << distribution << ": the moves never broke a kept pair, so the test shows little";
      EXPECT_EQ(tree.builds(), 1);
      EXPECT_EQ(tree.kept(), static_cast<Index>(sequence.size()) - 1);
    }
  }
}

// rebuild_every = 1 builds at every evaluation: the bytes of evaluations without a tree.
TEST(CoulombFmmTree, RebuiltEveryTimeGivesTheBytesOfNoTree) {
  const std::vector<Points> sequence = moving(make_points(5000, "clustered", 9), 4, 1e-3, 10);
  CoulombFmmTree tree(1);
  CoulombFmmOptions options;
  options.accuracy = 1e-2;
  for (const Points& X : sequence) {
    const CoulombEvaluation with = coulomb_fmm(X, options, nullptr, &tree);
    const CoulombEvaluation without = coulomb_fmm(X, options);
    EXPECT_EQ(with.energy, without.energy);
    EXPECT_TRUE(with.gradient == without.gradient);
  }
  EXPECT_EQ(tree.builds(), 4);
  EXPECT_EQ(tree.kept(), 0);
}

// The same sequence of inputs gives the same bytes on 1 and 2 threads, kept tree and split pairs included;
// the tree is rebuilt every 3 evaluations.
TEST(CoulombFmmTree, OutputsDependOnTheInputsNotOnTheThreads) {
  const Points X0 = make_points(6000, "uniform", 11);
  const std::vector<Points> sequence = moving(X0, 7, 0.2 * mean_spacing(X0), 12);
  std::vector<CoulombEvaluation> runs[2];
  const int threads_before = omp_get_max_threads();
  for (int run = 0; run < 2; ++run) {
    omp_set_num_threads(run == 0 ? 1 : 2);
    CoulombFmmTree tree(3);
    for (const Points& X : sequence) runs[run].push_back(coulomb_fmm(X, {}, nullptr, &tree));
    EXPECT_EQ(tree.builds(), 3);  // evaluations 1, 4 and 7
  }
  omp_set_num_threads(threads_before);
  for (size_t s = 0; s < sequence.size(); ++s) {
    EXPECT_EQ(runs[0][s].energy, runs[1][s].energy) << s;
    EXPECT_TRUE(runs[0][s].gradient == runs[1][s].gradient) << s;
  }
}

// Another point count or other parameters build the tree afresh.
TEST(CoulombFmmTree, AnotherSizeOrAccuracyBuildsAfresh) {
  CoulombFmmTree tree(1000);
  CoulombFmmOptions loose, tight;
  loose.accuracy = 1e-2;
  tight.accuracy = 1e-4;
  const Points a = make_points(3000, "uniform", 13), b = make_points(3500, "uniform", 14);
  CoulombFmmStats stats;
  coulomb_fmm(a, loose, &stats, &tree);
  coulomb_fmm(a, loose, &stats, &tree);
  EXPECT_TRUE(stats.kept_tree);
  coulomb_fmm(b, loose, &stats, &tree);
  EXPECT_FALSE(stats.kept_tree);
  const CoulombEvaluation fresh = coulomb_fmm(b, tight);
  const CoulombEvaluation built = coulomb_fmm(b, tight, &stats, &tree);
  EXPECT_FALSE(stats.kept_tree);
  EXPECT_TRUE(fresh.gradient == built.gradient);
  EXPECT_EQ(tree.builds(), 3);
  EXPECT_EQ(tree.kept(), 1);
  EXPECT_THROW(CoulombFmmTree(0), std::exception);
}

// The Coulomb iteration with its tree kept for 10 iterations reaches the form of the iteration that builds it
// every time, to within a small share of the shape's size: the fast sum's error moves the path, not the
// fixed point.
TEST(CoulombFmmTree, TheCoulombFormWithAKeptTreeIsTheFormWithout) {
  const Mesh mesh = torus(80, 50, 1.0, 0.35);  // 4,000 vertices: the fast summation
  CoulombCanonOptions options;
  options.energy.summation = CoulombOptions::Summation::Fast;
  options.tear_fraction = 0;
  options.max_iterations = 150;
  const CoulombCanonResult built = coulomb_canonical_form(mesh.V, mesh_edges(mesh.F), options);
  options.fmm_rebuild_every = 10;
  const CoulombCanonResult kept = coulomb_canonical_form(mesh.V, mesh_edges(mesh.F), options);
  const double diagonal = bbox_diagonal(built.X);
  EXPECT_LT(rigid_rms_distance(kept.X, built.X) / diagonal, 2e-3);
  EXPECT_NEAR(kept.energy / built.energy, 1.0, 1e-4);
}

}  // namespace coulomb_fmm_tree_test
}  // namespace cshapes
