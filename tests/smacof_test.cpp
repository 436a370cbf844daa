#include "cshapes/canon/smacof.h"

#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include <Eigen/QR>
#include <cmath>
#include <fstream>
#include <limits>
#include <random>
#include <sstream>

#include "cshapes/canon/classical_mds.h"
#include "cshapes/support/error.h"
#include "cshapes/geodesics/geodesics.h"
#include "cshapes/mesh/io.h"
#include "cshapes/data/synthetic.h"
#include "tests/test_support.h"

namespace cshapes {
namespace smacof_test {

Points random_points(Index n, unsigned seed, double spread = 1.0) {
  std::mt19937 rng(seed);
  std::normal_distribution<double> normal;
  Points P(n, 3);
  for (Index i = 0; i < n; ++i)
    for (int k = 0; k < 3; ++k) P(i, k) = spread * (k + 1) * normal(rng);
  return P;
}

DistanceMatrix euclidean_distances(const Points& P) {
  const Index n = P.rows();
  DistanceMatrix D(n, n);
  for (Index j = 0; j < n; ++j)
    for (Index i = 0; i < n; ++i) D(i, j) = static_cast<float>((P.row(i) - P.row(j)).norm());
  return D;
}

// Geodesic (graph) distances on a torus: a curved, non-Euclidean metric.
DistanceMatrix torus_geodesics(int nu = 40, int nv = 16) {
  return all_pairs_geodesics(torus(nu, nv, 2.0, 0.7));
}

// Dense reference: σ(X) = Σ_{i<j} wᵢwⱼ (δᵢⱼ − dᵢⱼ)² and X⁺ = V⁺ B(X) X with V = Σ wᵢⱼ (eᵢ − eⱼ)(eᵢ − eⱼ)ᵀ.
struct DenseGuttman {
  double stress = 0;
  Points X_next;
};
DenseGuttman dense_guttman(const DistanceMatrix& D, const Points& X, const Eigen::VectorXd& w) {
  const Index n = D.rows();
  Eigen::MatrixXd B = Eigen::MatrixXd::Zero(n, n), V = Eigen::MatrixXd::Zero(n, n);
  DenseGuttman out;
  for (Index i = 0; i < n; ++i)
    for (Index j = 0; j < n; ++j) {
      if (i == j) continue;
      const double wij = w[i] * w[j], d = (X.row(i) - X.row(j)).norm(), delta = D(i, j);
      if (i < j) out.stress += wij * (delta - d) * (delta - d);
      B(i, j) = d > 0 ? -wij * delta / d : 0.0;
      V(i, j) = -wij;
    }
  for (Index i = 0; i < n; ++i) {
    B(i, i) = -B.row(i).sum();
    V(i, i) = -V.row(i).sum();
  }
  Eigen::MatrixXd V_pinv = V.completeOrthogonalDecomposition().pseudoInverse();
  out.X_next = V_pinv * B * X;
  return out;
}

Points weighted_centred(const Points& X, const Eigen::VectorXd& w) {
  return X.rowwise() - (w.transpose() * X) / w.sum();
}

TEST(Smacof, GuttmanTransformMatchesDenseReference) {
  const Index n = 70;
  DistanceMatrix D =
      all_pairs_geodesics(icosphere(2)).topLeftCorner(n, n);  // non-Euclidean, connected enough
  Points X = random_points(n, 11);
  for (bool weighted : {false, true}) {
    Eigen::VectorXd w = weighted ? Eigen::VectorXd((Eigen::VectorXd::Random(n).array() + 1.5).matrix())
                                 : Eigen::VectorXd::Ones(n);
    GuttmanTransform fast = guttman_transform(D, X, weighted ? w : Eigen::VectorXd());
    DenseGuttman ref = dense_guttman(D, X, w);
    EXPECT_NEAR(fast.stress, ref.stress, 1e-5 * ref.stress) << "weighted " << weighted;
    Points ref_next = weighted_centred(ref.X_next, w);
    EXPECT_LE((fast.X_next - ref_next).norm(), 1e-5 * ref_next.norm()) << "weighted " << weighted;
    // The transform output is weighted-centred.
    EXPECT_LE(((w.transpose() * fast.X_next) / w.sum()).norm(), 1e-9 * ref_next.norm());
  }
}

TEST(Smacof, StressNeverIncreasesOnGeodesicDistances) {
  DistanceMatrix D = torus_geodesics();
  const Index n = D.rows();
  SmacofOptions options;
  options.max_iterations = 150;
  options.tolerance = 0;  // run every iteration: monotonicity must hold all the way
  for (const char* init : {"random", "cmds"}) {
    Points X0 = std::string(init) == "cmds" ? classical_mds(D).X : random_points(n, 3, 1.0);
    SmacofResult r = smacof(D, X0, options);
    ASSERT_EQ(r.stress_history.size(), 151u);
    for (size_t k = 1; k < r.stress_history.size(); ++k)
      // Single-precision distance arithmetic: the evaluated stress carries relative rounding of ~1e-7.
      ASSERT_LE(r.stress_history[k], r.stress_history[k - 1] * (1 + 1e-6)) << init << " iteration " << k;
    EXPECT_LT(r.normalized_stress, r.stress_history.front()) << init;
    EXPECT_TRUE(r.X.allFinite());
    EXPECT_EQ(r.stop_reason, "max iterations");
  }
}

TEST(Smacof, ReachesZeroStressOnEuclideanInput) {
  Points P = random_points(400, 5, 10.0);
  DistanceMatrix D = euclidean_distances(P);
  Points X0 = P + 0.3 * random_points(400, 6, 10.0);  // far from P, nothing to recover by luck
  SmacofOptions options;
  options.max_iterations = 2000;
  options.tolerance = 1e-12;
  options.target_stress = 1e-10;
  SmacofResult r = smacof(D, X0, options);
  EXPECT_GT(r.stress_history.front(), 1e-3);
  EXPECT_LE(r.normalized_stress, 1e-10) << r.stop_reason << " after " << r.iterations;
  // Initialised by classical MDS, it starts at zero (to float rounding).
  SmacofResult c = smacof(D, SmacofOptions{});
  EXPECT_LE(c.stress_history.front(), 1e-10);
}

TEST(Smacof, ExtrapolationReachesThePlainStressInFewerPasses) {
  DistanceMatrix D = torus_geodesics();
  Points X0 = random_points(D.rows(), 8, 1.0);
  SmacofOptions plain;
  plain.max_iterations = 400;
  plain.tolerance = 1e-6;
  SmacofResult p = smacof(D, X0, plain);
  for (SmacofAcceleration method : {SmacofAcceleration::Rre, SmacofAcceleration::Mpe}) {
    SmacofOptions fast = plain;
    fast.acceleration = method;
    fast.tolerance = 0;
    fast.target_stress = p.normalized_stress;
    SmacofResult a = smacof(D, X0, fast);
    EXPECT_EQ(a.stop_reason, "target stress") << to_string(method);
    EXPECT_LE(a.normalized_stress, p.normalized_stress) << to_string(method);
    EXPECT_LT(a.iterations, p.iterations) << to_string(method);
    EXPECT_GT(a.extrapolations_accepted, 0) << to_string(method);
    for (size_t k = 1; k < a.stress_history.size(); ++k)
      ASSERT_LE(a.stress_history[k], a.stress_history[k - 1] * (1 + 1e-6)) << to_string(method) << " " << k;
  }
}

TEST(Smacof, WeightsChangeTheObjectiveThatIsMinimised) {
  DistanceMatrix D = torus_geodesics(30, 12);
  const Index n = D.rows();
  // Heavy weights on the first third of the vertices.
  Eigen::VectorXd w = Eigen::VectorXd::Ones(n);
  w.head(n / 3).setConstant(20.0);
  Points X0 = classical_mds(D).X;
  SmacofOptions options;
  options.max_iterations = 300;
  options.tolerance = 1e-7;
  SmacofResult uniform = smacof(D, X0, options);
  options.vertex_weights = w;
  SmacofResult weighted = smacof(D, X0, options);
  auto stress_with = [&](const Points& X, const Eigen::VectorXd& weights) {
    return guttman_transform(D, X, weights).stress;
  };
  // Each solution is better than the other under its own weights.
  EXPECT_LT(stress_with(weighted.X, w), stress_with(uniform.X, w));
  EXPECT_LT(stress_with(uniform.X, {}), stress_with(weighted.X, {}));
  EXPECT_NEAR(weighted.stress, stress_with(weighted.X, w), 1e-6 * weighted.stress);
  // Invalid weights are refused.
  options.vertex_weights = w;
  options.vertex_weights[4] = 0;
  EXPECT_THROW(smacof(D, X0, options), Error);
  options.vertex_weights = w.head(n - 1);
  EXPECT_THROW(smacof(D, X0, options), Error);
}

TEST(Smacof, AreaWeightsAreVertexAreas) {
  Mesh g = grid(5, 5, 4.0, 4.0);  // 16 unit squares
  Eigen::VectorXd w = vertex_area_weights(g);
  EXPECT_NEAR(w.mean(), 1.0, 1e-12);
  // Interior vertices carry more area than corners (each triangle gives a third of its area to each corner).
  EXPECT_GT(w[2 * 5 + 2], w[0]);
}

TEST(Smacof, RefusesInfiniteNanAndAsymmetricDistances) {
  Points P = random_points(40, 9);
  DistanceMatrix D = euclidean_distances(P);
  DistanceMatrix bad = D;
  bad(5, 30) = bad(30, 5) = std::numeric_limits<float>::infinity();
  try {
    smacof(bad, P, SmacofOptions{});
    FAIL() << "an infinite distance was accepted";
  } catch (const Error& e) {
    // One infinite pair among finite ones is a failed computation, not a disconnected mesh.
    EXPECT_EQ(std::string(e.what()).find("disconnected"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("failed"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("(5, 30)"), std::string::npos) << e.what();
  }
  bad = D;  // two components: points < 10 and the rest
  bad.topRightCorner(10, 30).setConstant(std::numeric_limits<float>::infinity());
  bad.bottomLeftCorner(30, 10).setConstant(std::numeric_limits<float>::infinity());
  try {
    smacof(bad, P, SmacofOptions{});
    FAIL() << "an infinite distance was accepted";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("disconnected"), std::string::npos) << e.what();
  }
  bad = D;
  bad(2, 3) = bad(3, 2) = std::numeric_limits<float>::quiet_NaN();
  EXPECT_THROW(smacof(bad, P, SmacofOptions{}), Error);
  bad = D;
  bad(2, 3) += 1.0f;
  EXPECT_THROW(smacof(bad, P, SmacofOptions{}), Error);
  Points nan_start = P;
  nan_start(0, 0) = std::numeric_limits<double>::quiet_NaN();
  EXPECT_THROW(smacof(D, nan_start, SmacofOptions{}), Error);
}

TEST(Smacof, CoincidentStartingPointsStayFinite) {
  DistanceMatrix D = torus_geodesics(20, 8);
  Points X0 = random_points(D.rows(), 10);
  X0.row(3) = X0.row(4);  // d = 0: the pair contributes nothing to B(X), never a division by zero
  SmacofOptions options;
  options.max_iterations = 20;
  SmacofResult r = smacof(D, X0, options);
  EXPECT_TRUE(r.X.allFinite());
}

TEST(SmacofCli, CanonWritesHistoryAndFiniteForm) {
  std::string dir = test::scratch_dir("smacof");
  Mesh mesh = torus(30, 12, 2.0, 0.6);
  write_mesh(dir + "/torus.off", mesh);
  write_distance_matrix(dir + "/D.bin", all_pairs_geodesics(mesh));
  for (const char* source : {"--geodesics graph", "--distances D.bin"}) {
    std::string args =
        std::string(source) == "--distances D.bin" ? "--distances '" + dir + "/D.bin'" : source;
    auto r =
        test::run_cli("-q canon '" + dir + "/torus.off' -o '" + dir + "/out.off' --method smacof " + args +
                      " --smacof-max-iterations 30 --accelerate rre --history '" + dir + "/h.csv' --json");
    ASSERT_EQ(r.exit_code, 0) << r.err;
    Mesh out = read_mesh(dir + "/out.off");
    EXPECT_EQ(out.F, mesh.F);
    EXPECT_TRUE(out.V.allFinite());
    std::ifstream history(dir + "/h.csv");
    std::string line;
    std::getline(history, line);
    EXPECT_EQ(line, "iteration,passes,normalized_stress,extrapolated");
    double previous = std::numeric_limits<double>::infinity();
    int rows = 0;
    while (std::getline(history, line)) {
      std::stringstream s(line);
      std::string cell;
      for (int c = 0; c < 3; ++c) std::getline(s, cell, ',');
      double stress = std::stod(cell);
      EXPECT_LE(stress, previous * (1 + 1e-6));
      previous = stress;
      ++rows;
    }
    EXPECT_GT(rows, 5);
  }
  auto bad = test::run_cli("-q canon '" + dir + "/torus.off' -o '" + dir +
                           "/out.off' --method smacof "
                           "--geodesics graph --accelerate bogus");
  EXPECT_NE(bad.exit_code, 0);
  EXPECT_NE(bad.err.find("rre"), std::string::npos) << bad.err;
}

TEST(SmacofCli, BenchAgreesWithScikitLearnOnTheSameProblem) {
  auto r = test::run_cli("-q bench smacof --points 300 --iterations 5 --json");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  nlohmann::json j = nlohmann::json::parse(r.out);
  EXPECT_EQ(j["n"], 300);
  EXPECT_GT(j["seconds_per_iteration"].get<double>(), 0);
  EXPECT_GT(j["peak_rss_mb"].get<double>(), 0);
  EXPECT_LT(j["normalized_stress_end"].get<double>(), j["normalized_stress_start"].get<double>());
  if (!j["reference"].contains("stress"))
    GTEST_SKIP() << "scikit-learn not available: " << j["reference"].dump();
  // Same matrix, same start, same number of Guttman transforms: the same stress, to float rounding.
  EXPECT_LT(j["reference"]["stress_relative_difference"].get<double>(), 1e-5);
  EXPECT_GT(j["speedup_vs_reference"].get<double>(), 0);
}

}  // namespace smacof_test
}  // namespace cshapes
