#include "cshapes/canon/classical_mds.h"

#include <gtest/gtest.h>
#include <omp.h>

#include <nlohmann/json.hpp>

#include <Eigen/Eigenvalues>
#include <Eigen/SVD>
#include <cmath>
#include <limits>
#include <random>

#include "cshapes/support/error.h"
#include "cshapes/geodesics/geodesics.h"
#include "cshapes/mesh/io.h"
#include "cshapes/data/synthetic.h"
#include "tests/test_support.h"

namespace cshapes {
namespace classical_mds_test {

Points random_points(Index n, unsigned seed, Eigen::Vector3d scale = {3.0, 2.0, 1.0}) {
  std::mt19937 rng(seed);
  std::normal_distribution<double> normal;
  Points P(n, 3);
  for (Index i = 0; i < n; ++i)
    for (int k = 0; k < 3; ++k) P(i, k) = scale[k] * normal(rng) + 10.0;  // off-centre on purpose
  return P;
}

Eigen::MatrixXd euclidean_distances(const Points& P) {
  const Index n = P.rows();
  Eigen::MatrixXd D(n, n);
  for (Index j = 0; j < n; ++j)
    for (Index i = 0; i < n; ++i) D(i, j) = (P.row(i) - P.row(j)).norm();
  return D;
}

// min over orthogonal Q (reflections allowed: MDS cannot tell mirror images) and translations of
// ‖X Q + t − P‖_F, relative to ‖P − mean(P)‖_F.
double procrustes_residual(const Points& X, const Points& P) {
  Points Xc = X.rowwise() - X.colwise().mean();
  Points Pc = P.rowwise() - P.colwise().mean();
  Eigen::JacobiSVD<Eigen::Matrix3d> svd(Xc.transpose() * Pc, Eigen::ComputeFullU | Eigen::ComputeFullV);
  Eigen::Matrix3d Q = svd.matrixU() * svd.matrixV().transpose();
  return (Xc * Q - Pc).norm() / Pc.norm();
}

// Dense B = −½ J (D∘D) J, the reference.
Eigen::MatrixXd dense_b(const Eigen::MatrixXd& D) {
  const Index n = D.rows();
  Eigen::MatrixXd J = Eigen::MatrixXd::Identity(n, n) - Eigen::MatrixXd::Constant(n, n, 1.0 / n);
  return -0.5 * J * D.array().square().matrix() * J;
}

// Great-circle distances between points of an icosphere: a metric that no 3-D point set realises.
Eigen::MatrixXd sphere_geodesics(int subdivisions) {
  Mesh s = icosphere(subdivisions);
  const Index n = s.num_vertices();
  Eigen::MatrixXd D(n, n);
  for (Index j = 0; j < n; ++j)
    for (Index i = 0; i < n; ++i)
      D(i, j) = i == j ? 0.0 : std::acos(std::clamp(s.V.row(i).dot(s.V.row(j)), -1.0, 1.0));
  return D;
}

TEST(ClassicalMds, RecoversEuclideanPointsUpToRigidMotion) {
  Points P = random_points(300, 1);
  ClassicalMdsOptions options;
  options.tolerance = 1e-13;
  ClassicalMdsResult r = classical_mds(euclidean_distances(P), options);
  EXPECT_LE(procrustes_residual(r.X, P), 1e-8);
  // Known answer: the eigenvalues of B = Pc Pcᵀ are those of the 3×3 scatter matrix Pcᵀ Pc.
  Points Pc = P.rowwise() - P.colwise().mean();
  Eigen::Vector3d scatter = Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d>(Pc.transpose() * Pc).eigenvalues();
  for (int k = 0; k < 3; ++k) EXPECT_NEAR(r.eigenvalues[k], scatter[2 - k], 1e-9 * scatter[2]);
  EXPECT_NEAR(r.trace, Pc.squaredNorm(), 1e-9 * Pc.squaredNorm());
  EXPECT_NEAR(r.explained_energy, 1.0, 1e-9);
  EXPECT_NEAR(r.most_negative_eigenvalue, 0.0, 1e-8 * r.eigenvalues[0]);
  EXPECT_NEAR(r.negative_mass_lower_bound, 0.0, 1e-9);
  // Centred at the origin.
  EXPECT_LE(r.X.colwise().mean().norm(), 1e-9 * std::sqrt(r.eigenvalues[0]));
}

TEST(ClassicalMds, SinglePrecisionMatrixToFloatAccuracy) {
  Points P = random_points(400, 2);
  DistanceMatrix D = euclidean_distances(P).cast<float>();
  ClassicalMdsResult r = classical_mds(D);
  // Squared float distances carry relative errors ~1e-7; the embedding inherits them.
  EXPECT_LE(procrustes_residual(r.X, P), 1e-5);
}

TEST(ClassicalMds, ScaleAndPermutationCovariance) {
  Points P = random_points(120, 3);
  Eigen::MatrixXd D = euclidean_distances(P);
  ClassicalMdsResult a = classical_mds(D);
  ClassicalMdsResult b = classical_mds(Eigen::MatrixXd(D * 1e6));
  EXPECT_LE(procrustes_residual(b.X / 1e6, a.X), 1e-8);
  for (int k = 0; k < 3; ++k) EXPECT_NEAR(b.eigenvalues[k], 1e12 * a.eigenvalues[k], 1e-8 * b.eigenvalues[0]);
}

TEST(ClassicalMds, SpectrumSummariesMatchDenseEigendecomposition) {
  Eigen::MatrixXd D = sphere_geodesics(2);  // 162 points
  Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> dense(dense_b(D));
  const Eigen::VectorXd lambda = dense.eigenvalues();  // ascending
  const Index n = lambda.size();
  ClassicalMdsOptions options;
  options.tolerance = 1e-12;
  ClassicalMdsResult r = classical_mds(D, options);
  const double scale = lambda[n - 1];
  for (int k = 0; k < 3; ++k) EXPECT_NEAR(r.eigenvalues[k], lambda[n - 1 - k], 1e-9 * scale);
  EXPECT_NEAR(r.most_negative_eigenvalue, lambda[0], 1e-9 * scale);
  EXPECT_LT(lambda[0], -1e-3 * scale) << "great-circle distances should not be Euclidean";
  EXPECT_NEAR(r.trace, lambda.sum(), 1e-9 * lambda.cwiseAbs().sum());
  EXPECT_NEAR(r.frobenius_squared, lambda.squaredNorm(), 1e-9 * lambda.squaredNorm());
  // The reported bounds hold for the true negative part of the spectrum.
  const double top_sum = lambda.tail(3).sum();
  const double negative_mass = -(lambda.array() < 0).select(lambda.array(), 0.0).sum();
  const double negative_energy = (lambda.array() < 0).select(lambda.array().square(), 0.0).sum();
  EXPECT_LE(r.negative_mass_lower_bound, negative_mass / top_sum + 1e-12);
  EXPECT_GT(r.negative_mass_lower_bound, 0);
  EXPECT_GE(r.negative_energy_upper_bound, negative_energy / lambda.squaredNorm() - 1e-12);
  // The embedding is the dense one up to a rotation within the top eigenspace (the sphere's symmetry makes
  // λ₁ = λ₂ = λ₃): compare the Gram matrices X Xᵀ = Σ λₖ vₖ vₖᵀ.
  Eigen::MatrixXd top = dense.eigenvectors().rightCols(3);
  Eigen::MatrixXd gram = top * lambda.tail(3).asDiagonal() * top.transpose();
  EXPECT_LE((r.X * r.X.transpose() - gram).norm(), 1e-8 * gram.norm());
}

TEST(ClassicalMds, PlanarPointsGiveAZeroThirdAxis) {
  Points P = random_points(100, 4);
  P.col(2).setConstant(5.0);
  ClassicalMdsResult r = classical_mds(euclidean_distances(P));
  EXPECT_TRUE(r.X.allFinite());
  EXPECT_LE(std::abs(r.eigenvalues[2]), 1e-9 * r.eigenvalues[0]);
  EXPECT_LE(procrustes_residual(r.X, P), 1e-7);
}

TEST(ClassicalMds, RefusesInfiniteAndNegativeDistances) {
  Points P = random_points(50, 5);
  DistanceMatrix D = euclidean_distances(P).cast<float>();
  D(7, 3) = D(3, 7) = std::numeric_limits<float>::infinity();
  try {
    classical_mds(D);
    FAIL() << "an infinite distance was accepted";
  } catch (const Error& e) {
    // One infinite pair among finite ones is a failed computation, not a disconnected mesh.
    EXPECT_EQ(std::string(e.what()).find("disconnected"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("failed"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("(3, 7)"), std::string::npos) << e.what();
  }
  DistanceMatrix split = euclidean_distances(P).cast<float>();  // two components: points < 20 and the rest
  split.topRightCorner(20, 30).setConstant(std::numeric_limits<float>::infinity());
  split.bottomLeftCorner(30, 20).setConstant(std::numeric_limits<float>::infinity());
  try {
    classical_mds(split);
    FAIL() << "an infinite distance was accepted";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("disconnected"), std::string::npos) << e.what();
  }
  D(7, 3) = D(3, 7) = std::numeric_limits<float>::quiet_NaN();
  EXPECT_THROW(classical_mds(D), Error);
  D(7, 3) = D(3, 7) = -1.0f;
  EXPECT_THROW(classical_mds(D), Error);
  EXPECT_THROW(classical_mds(DistanceMatrix(DistanceMatrix::Zero(3, 3))), Error);
}

// Pairwise distances of the rows of X.
Eigen::MatrixXd embedding_distances(const Points& X) {
  return euclidean_distances(X);
}

TEST(ClassicalMds, RegularTetrahedronKnownAnswer) {
  // Four points at unit distance: B = X Xᵀ of a regular tetrahedron of edge 1 (circumradius √(3/8)), so
  // tr B = 4 · 3/8 and λ₁ = λ₂ = λ₃ = 1/2; the fourth eigenvalue (the constant vector) is 0. n = 4 is below
  // any Lanczos subspace: the dense path.
  Eigen::MatrixXd D = Eigen::MatrixXd::Ones(4, 4) - Eigen::MatrixXd::Identity(4, 4);
  ClassicalMdsResult r = classical_mds(D);
  for (int k = 0; k < 3; ++k) EXPECT_NEAR(r.eigenvalues[k], 0.5, 1e-12);
  EXPECT_NEAR(r.most_negative_eigenvalue, 0.0, 1e-12);
  EXPECT_NEAR(r.trace, 1.5, 1e-12);
  EXPECT_NEAR(r.explained_energy, 1.0, 1e-12);
  EXPECT_EQ(r.matrix_products, 0);
  EXPECT_LE((embedding_distances(r.X) - D).cwiseAbs().maxCoeff(), 1e-12);
  // In single precision too (the geodesic matrices' type).
  ClassicalMdsResult f = classical_mds(DistanceMatrix(D.cast<float>()));
  EXPECT_LE((embedding_distances(f.X) - D).cwiseAbs().maxCoeff(), 1e-6);
}

TEST(ClassicalMds, OctahedronSurfaceDistancesKnownAnswer) {
  // The octahedron ±eₖ with its surface (geodesic) distances: √2 between neighbours, √6 between opposite
  // vertices (across two faces, 2 × the height √(3/2) of a face of edge √2). Not Euclidean. With vertices
  // ordered (e₁, −e₁, e₂, −e₂, e₃, −e₃): (D∘D) v = −6 v for v = e.g. (1, −1, 0, 0, 0, 0), so B v = 3 v three
  // times, and the embedding is √(3/2)·(±eₖ): neighbours √3 apart, opposite vertices √6. The other
  // eigenvalues: −1 (twice, v = (1, 1, −1, −1, 0, 0)) and 0 (the constant vector).
  Eigen::MatrixXd D(6, 6);
  for (int i = 0; i < 6; ++i)
    for (int j = 0; j < 6; ++j) D(i, j) = i == j ? 0.0 : i / 2 == j / 2 ? std::sqrt(6.0) : std::sqrt(2.0);
  ClassicalMdsResult r = classical_mds(D);
  for (int k = 0; k < 3; ++k) EXPECT_NEAR(r.eigenvalues[k], 3.0, 1e-12);
  EXPECT_NEAR(r.most_negative_eigenvalue, -1.0, 1e-12);
  const Eigen::MatrixXd E = embedding_distances(r.X);
  for (int i = 0; i < 6; ++i)
    for (int j = 0; j < 6; ++j)
      EXPECT_NEAR(E(i, j),
                  i == j           ? 0.0
                  : i / 2 == j / 2 ? std::sqrt(6.0)
                                   : std::sqrt(3.0),
                  1e-12)
          << i << ", " << j;
}

TEST(ClassicalMds, DenseAndLanczosPathsAgree) {
  // 162 points: dense by default; Lanczos when forced (dense_below = 0). Same spectrum, same Gram matrix.
  Eigen::MatrixXd D = sphere_geodesics(2);
  ClassicalMdsOptions lanczos;
  lanczos.dense_below = 0;
  lanczos.tolerance = 1e-12;
  ClassicalMdsResult a = classical_mds(D), b = classical_mds(D, lanczos);
  EXPECT_EQ(a.matrix_products, 0);
  EXPECT_GT(b.matrix_products, 0);
  const double scale = a.eigenvalues[0];
  for (int k = 0; k < 3; ++k) EXPECT_NEAR(a.eigenvalues[k], b.eigenvalues[k], 1e-9 * scale);
  EXPECT_NEAR(a.most_negative_eigenvalue, b.most_negative_eigenvalue, 1e-9 * scale);
  EXPECT_NEAR(a.explained_energy, b.explained_energy, 1e-9);
  const Eigen::MatrixXd gram_a = a.X * a.X.transpose(), gram_b = b.X * b.X.transpose();
  EXPECT_LE((gram_a - gram_b).norm(), 1e-8 * gram_a.norm());
}

TEST(ClassicalMds, BitIdenticalForAnyThreadCount) {
  // Issue 22: `canon --method cmds` differed between 1 and 2 threads (up to 8e-13); SMACOF and Coulomb do
  // not. 1,100 points: the Lanczos path, with several tiles of the product per thread.
  const Eigen::MatrixXd D = sphere_geodesics(4).topLeftCorner(1100, 1100);
  const int before = omp_get_max_threads();
  std::vector<ClassicalMdsResult> runs;
  for (int threads : {1, 2, 3, 4}) {
    omp_set_num_threads(threads);
    runs.push_back(classical_mds(D));
  }
  omp_set_num_threads(before);
  for (size_t k = 1; k < runs.size(); ++k) {
    EXPECT_EQ(runs[k].X, runs[0].X) << "threads " << k + 1;
    EXPECT_EQ(runs[k].eigenvalues, runs[0].eigenvalues) << "threads " << k + 1;
  }
}

TEST(ClassicalMdsCli, CanonOfSmallClosedMeshes) {
  // 4 to 8 vertices: below any Lanczos subspace (Spectra refused them with "ncv must satisfy nev < ncv <=
  // n").
  std::string dir = test::scratch_dir("cmds-small");
  test::write_text(dir + "/tetra.off",
                   "OFF\n4 4 6\n1 1 1\n1 -1 -1\n-1 1 -1\n-1 -1 1\n"
                   "3 0 1 2\n3 0 3 1\n3 0 2 3\n3 1 3 2\n");
  test::write_text(dir + "/octa.off",
                   "OFF\n6 8 12\n1 0 0\n-1 0 0\n0 1 0\n0 -1 0\n0 0 1\n0 0 -1\n"
                   "3 0 2 4\n3 2 1 4\n3 1 3 4\n3 3 0 4\n3 2 0 5\n3 1 2 5\n3 3 1 5\n3 0 3 5\n");
  test::write_text(dir + "/cube.off",
                   "OFF\n8 12 18\n0 0 0\n1 0 0\n1 1 0\n0 1 0\n0 0 1\n1 0 1\n1 1 1\n0 1 1\n"
                   "3 0 2 1\n3 0 3 2\n3 4 5 6\n3 4 6 7\n3 0 1 5\n3 0 5 4\n"
                   "3 1 2 6\n3 1 6 5\n3 2 3 7\n3 2 7 6\n3 3 0 4\n3 3 4 7\n");
  for (const char* shape : {"tetra", "octa", "cube"})
    for (const char* method : {"cmds", "smacof"}) {
      SCOPED_TRACE(std::string(shape) + " " + method);
      const std::string in = dir + "/" + shape + ".off", out = dir + "/" + shape + "-" + method + ".off";
      auto r =
          test::run_cli("-q canon '" + in + "' -o '" + out + "' --method " + method + " --geodesics exact");
      ASSERT_EQ(r.exit_code, 0) << r.err;
      Mesh form = read_mesh(out);
      EXPECT_TRUE(form.V.allFinite());
      if (std::string(shape) == "tetra") {
        // Geodesics on a regular tetrahedron are its edges: the form is the input up to a rigid motion.
        const Mesh input = read_mesh(in);
        EXPECT_LE((embedding_distances(form.V) - euclidean_distances(input.V)).cwiseAbs().maxCoeff(), 1e-4);
      }
    }
}

TEST(ClassicalMdsCli, CanonWritesFiniteFormWithTheInputsFaces) {
  std::string dir = test::scratch_dir("cmds");
  Mesh mesh = torus(24, 12, 2.0, 0.6);
  write_mesh(dir + "/torus.off", mesh);
  auto r = test::run_cli("-q canon '" + dir + "/torus.off' -o '" + dir +
                         "/out.off' --method cmds --geodesics graph --json");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  Mesh out = read_mesh(dir + "/out.off");
  EXPECT_EQ(out.num_vertices(), mesh.num_vertices());
  EXPECT_EQ(out.F, mesh.F);
  EXPECT_TRUE(out.V.allFinite());
  EXPECT_NE(r.out.find("most_negative_eigenvalue"), std::string::npos);
}

TEST(ClassicalMdsCli, DisconnectedMeshIsRepairedOrRefusedWithStrict) {
  std::string dir = test::scratch_dir("cmds-disc");
  Mesh a = icosphere(1), b = icosphere(1);
  Mesh both;
  both.V.resize(a.V.rows() * 2, 3);
  both.V << a.V, (b.V.rowwise() + Eigen::RowVector3d(5, 0, 0));
  both.F.resize(a.F.rows() * 2, 3);
  both.F << a.F, (b.F.array() + static_cast<int>(a.V.rows())).matrix();
  write_mesh(dir + "/two.off", both);
  // --strict refuses, naming the defect.
  auto r = test::run_cli("-q canon '" + dir + "/two.off' -o '" + dir +
                         "/out.ply' --method cmds --geodesics graph --strict");
  EXPECT_NE(r.exit_code, 0);
  EXPECT_NE(r.err.find("2 components"), std::string::npos) << r.err;
  // By default the largest component is kept (the first sphere on a tie); the dropped sphere cannot go to
  // OFF, and goes to PLY as NaN rows with valid = 0, so the form has the input's vertex count.
  r = test::run_cli("-q canon '" + dir + "/two.off' -o '" + dir +
                    "/out.off' --method cmds --geodesics graph");
  EXPECT_NE(r.exit_code, 0);
  EXPECT_NE(r.err.find("write .ply"), std::string::npos) << r.err;
  r = test::run_cli("-q canon '" + dir + "/two.off' -o '" + dir +
                    "/out.ply' --method cmds --geodesics graph");
  EXPECT_EQ(r.exit_code, 0) << r.err;
  // A distance matrix of the whole input (infinite between the spheres): restricted to the kept component.
  const Index m = a.num_vertices();
  DistanceMatrix D = DistanceMatrix::Constant(2 * m, 2 * m, std::numeric_limits<float>::infinity());
  D.topLeftCorner(m, m) = all_pairs_geodesics(a);
  D.bottomRightCorner(m, m) = all_pairs_geodesics(a);  // the second sphere is a translated copy
  write_distance_matrix(dir + "/D.bin", D);
  r = test::run_cli("canon '" + dir + "/two.off' -o '" + dir + "/out2.ply' --method cmds --distances '" +
                    dir + "/D.bin' --json");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  nlohmann::json summary = nlohmann::json::parse(r.out);
  EXPECT_EQ(summary["input_vertices"], 2 * m);
  EXPECT_EQ(summary["kept_input_vertices"], m);
}

}  // namespace classical_mds_test
}  // namespace cshapes
