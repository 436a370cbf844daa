// Laplace–Beltrami eigenpairs (operators/laplace_beltrami.h) against analytic spectra, the sparse solver against
// the dense one, and the spectral canonical forms (canon/spectral_embedding.h; methods lbo and diffusion):
// isometry invariance up to signs, scale equivariance, diffusion distances against a brute-force sum over
// all eigenpairs, and sign flips undone by the shape distance distmat uses.
#include <gtest/gtest.h>
#include <omp.h>

#include <cmath>
#include <nlohmann/json.hpp>
#include <random>

#include "cshapes/canon/spectral_embedding.h"
#include "cshapes/data/articulated.h"
#include "cshapes/operators/laplace_beltrami.h"
#include "cshapes/data/synthetic.h"
#include "cshapes/matching/shape_distance.h"
#include "cshapes/pipeline/canonical_forms.h"

namespace cshapes {
namespace spectral_test {

// Largest relative error of values[1..] against exact[1..] (λ_0 = 0 is checked absolutely elsewhere).
double worst_relative_error(const Eigen::VectorXd& values, const std::vector<double>& exact) {
  double worst = 0;
  for (size_t i = 1; i < exact.size(); ++i)
    worst = std::max(worst, std::abs(values[static_cast<Index>(i)] - exact[i]) / exact[i]);
  return worst;
}

// The unit sphere: λ = l(l+1) with multiplicity 2l+1, l = 0..3 (16 eigenvalues).
std::vector<double> sphere_spectrum() {
  std::vector<double> exact;
  for (int l = 0; l <= 3; ++l)
    for (int m = 0; m < 2 * l + 1; ++m) exact.push_back(l * (l + 1.0));
  return exact;
}

// The a×b rectangle with free (Neumann) boundary: λ = (πm/a)² + (πn/b)²; for a = 2.5, b = 1 the six
// smallest are (m, n) = (0,0), (1,0), (2,0), (0,1), (1,1), (3,0), all simple.
constexpr double kA = 2.5, kB = 1.0;
std::vector<double> rectangle_spectrum() {
  auto lambda = [](int m, int n) { return std::pow(M_PI * m / kA, 2) + std::pow(M_PI * n / kB, 2); };
  return {0, lambda(1, 0), lambda(2, 0), lambda(0, 1), lambda(1, 1), lambda(3, 0)};
}

// The rectangle with obtuse triangles: interior columns shifted by ±0.35 of a spacing, alternately per
// row, rows 0.3 column spacings apart (nx = 10r + 1, ny = 13r + 1). The boundary stays straight.
Mesh skewed_rectangle(int r) {
  const int nx = 10 * r + 1, ny = 13 * r + 1;
  Mesh m = grid(nx, ny, kA, kB);
  const double hx = kA / (nx - 1);
  for (int j = 0; j < ny; ++j)
    for (int i = 1; i + 1 < nx; ++i) m.V(j * nx + i, 0) += 0.35 * hx * (j % 2 ? 1 : -1);
  return m;
}

LaplaceBeltramiOptions with_eigenpairs(int k, bool intrinsic_delaunay = true) {
  LaplaceBeltramiOptions o;
  o.eigenpairs = k;
  o.intrinsic_delaunay = intrinsic_delaunay;
  return o;
}

TEST(LaplaceBeltrami, UnitSphereSpectrumConvergesWithMultiplicities) {
  // Measured: 1.44% (642 vertices), 0.36% (2,562): second order, as the cotangent Laplacian should be.
  const std::vector<double> exact = sphere_spectrum();
  const LaplaceBeltramiEigen coarse = laplace_beltrami_eigen(icosphere(3), with_eigenpairs(16));
  const LaplaceBeltramiEigen fine = laplace_beltrami_eigen(icosphere(4), with_eigenpairs(16));
  EXPECT_NE(coarse.solver.find("shift-invert"), std::string::npos) << coarse.solver;
  const double coarse_error = worst_relative_error(coarse.values, exact);
  const double fine_error = worst_relative_error(fine.values, exact);
  EXPECT_LT(coarse_error, 0.02);
  EXPECT_LT(fine_error, 0.005);
  EXPECT_LT(fine_error, coarse_error / 3);  // h halved: the error falls about fourfold
  EXPECT_NEAR(fine.values[0], 0, 1e-8);
  EXPECT_NEAR(fine.area, 4 * M_PI, 0.01 * 4 * M_PI);
  // Multiplicities 3, 5, 7 reported as near-multiple groups (λ0 = 0 alone: one component).
  const std::vector<std::vector<int>> groups = {{1, 2, 3}, {4, 5, 6, 7, 8}, {9, 10, 11, 12, 13, 14, 15}};
  EXPECT_EQ(fine.near_multiple, groups);
  EXPECT_NE(near_multiple_description(fine).find("λ1..λ3"), std::string::npos);
}

TEST(LaplaceBeltrami, NeumannRectangleSpectrumConverges) {
  // Measured: 1.38% (26×11 vertices), 0.35% (51×21).
  const std::vector<double> exact = rectangle_spectrum();
  const double coarse = worst_relative_error(
      laplace_beltrami_eigen(grid(26, 11, kA, kB), with_eigenpairs(6)).values, exact);
  const double fine = worst_relative_error(
      laplace_beltrami_eigen(grid(51, 21, kA, kB), with_eigenpairs(6)).values, exact);
  EXPECT_LT(coarse, 0.02);
  EXPECT_LT(fine, 0.005);
  EXPECT_LT(fine, coarse / 3);
}

TEST(LaplaceBeltrami, IntrinsicDelaunayIsTheMoreAccurateOnObtuseTriangles) {
  // Why it is the default. Measured (max relative error of λ1..λ5): intrinsic Delaunay 2.6%, 0.65%, 0.17%
  // at r = 1, 2, 4; the mesh's own cotangents 2.5%, 2.3%, 0.70% (no clean convergence).
  const std::vector<double> exact = rectangle_spectrum();
  auto error = [&](int r, bool idt) {
    return worst_relative_error(laplace_beltrami_eigen(skewed_rectangle(r), with_eigenpairs(6, idt)).values,
                                exact);
  };
  const double idt1 = error(1, true), idt2 = error(2, true), cot2 = error(2, false);
  EXPECT_LT(idt2, idt1 / 3);
  EXPECT_LT(idt2, cot2 / 2);
  EXPECT_GT(laplace_beltrami_matrices(skewed_rectangle(2), with_eigenpairs(6)).flips, 0);
}

TEST(LaplaceBeltrami, ShiftInvertAgreesWithTheDenseSolver) {
  const Mesh mesh = torus(40, 16);  // 640 vertices: above kDenseEigenVertices
  const LaplacianMatrices A = cotangent_laplacian(mesh);
  const LaplaceBeltramiEigen sparse = laplace_beltrami_eigen(A, with_eigenpairs(20));
  const LaplaceBeltramiEigen dense = laplace_beltrami_eigen_dense(A);
  ASSERT_NE(sparse.solver, "dense");
  for (Index i = 1; i < 20; ++i) EXPECT_NEAR(sparse.values[i], dense.values[i], 1e-8 * dense.values[i]) << i;
  // Eigenvectors: M-orthonormal, and L φ = λ M φ to the solver's tolerance.
  const Eigen::MatrixXd gram = sparse.vectors.transpose() * sparse.mass.asDiagonal() * sparse.vectors;
  EXPECT_LT((gram - Eigen::MatrixXd::Identity(20, 20)).cwiseAbs().maxCoeff(), 1e-8);
  for (Index i = 1; i < 20; ++i) {
    const Eigen::VectorXd residual =
        A.L * sparse.vectors.col(i) - sparse.values[i] * A.mass.cwiseProduct(sparse.vectors.col(i));
    EXPECT_LT(residual.norm(), 1e-6 * sparse.values[i] * A.mass.cwiseProduct(sparse.vectors.col(i)).norm());
  }
}

TEST(LaplaceBeltrami, PointCloudGraphLaplacianApproachesTheSphereSpectrum) {
  // kNN graph Laplacian of 3,000 points sampled on the unit sphere. Measured λ1..λ8: k = 8 about 20% low,
  // k = 32 within 7% (1.90-1.97, 5.59-5.85): the kernel's truncation shrinks with more neighbours.
  std::mt19937_64 rng(1);
  Mesh cloud;
  cloud.V = sample_surface(icosphere(5), 3000, rng);
  KnnGraphOptions knn;
  knn.k = 32;
  const LaplaceBeltramiEigen e = laplace_beltrami_eigen(cloud, with_eigenpairs(10), knn);
  EXPECT_EQ(e.laplacian, "knn-graph");
  EXPECT_LT(worst_relative_error(e.values.head(9), {0, 2, 2, 2, 6, 6, 6, 6, 6}), 0.1);
}

TEST(LaplaceBeltrami, SeveralComponentsGiveAMultipleZero) {
  Mesh two = icosphere(3);
  Mesh other = icosphere(3);
  other.V.col(0).array() += 5;
  Mesh both;
  both.V.resize(2 * two.num_vertices(), 3);
  both.V << two.V, other.V;
  both.F.resize(2 * two.num_faces(), 3);
  both.F << two.F, other.F.array() + static_cast<int>(two.num_vertices());
  const LaplaceBeltramiEigen e = laplace_beltrami_eigen(both, with_eigenpairs(8));
  EXPECT_NEAR(e.values[1], 0, 1e-8);
  ASSERT_FALSE(e.near_multiple.empty());
  EXPECT_EQ(e.near_multiple.front(), (std::vector<int>{0, 1}));
  EXPECT_THROW(gps_embedding(e), Error);  // λ_1 = 0: the methods keep one component first
}

// A flat 4×1 strip and the same strip bent into a half cylinder (an isometry; the triangles' edges become
// chords, 0.03% shorter).
Mesh strip() {
  return grid(41, 11, 4.0, 1.0);
}
Mesh bent_strip() {
  Mesh m = strip();
  const double R = 4.0 / M_PI;
  for (Index v = 0; v < m.num_vertices(); ++v) {
    const double x = m.V(v, 0);
    m.V(v, 0) = R * std::sin(x / R);
    m.V(v, 2) = R * (1 - std::cos(x / R));
  }
  return m;
}

TEST(SpectralForms, EigenmapOfAnIsometricDeformationIsTheSameUpToSigns) {
  const LaplaceBeltramiEigen flat = laplace_beltrami_eigen(strip(), with_eigenpairs(6));
  const LaplaceBeltramiEigen bent = laplace_beltrami_eigen(bent_strip(), with_eigenpairs(6));
  for (Index i = 1; i < 6; ++i) EXPECT_NEAR(bent.values[i], flat.values[i], 1e-3 * flat.values[i]) << i;
  const Points A = gps_embedding(flat), B = gps_embedding(bent);
  const double extent = (A.colwise().maxCoeff() - A.colwise().minCoeff()).maxCoeff();
  for (int c = 0; c < 3; ++c) {
    const double sign = A.col(c).dot(B.col(c)) >= 0 ? 1 : -1;
    EXPECT_LT((A.col(c) - sign * B.col(c)).cwiseAbs().maxCoeff(), 1e-3 * extent) << "axis " << c;
  }
}

TEST(SpectralForms, PosesOfAnArticulatedShapeGetNearlyTheSameForm) {
  // The generated articulated shapes are near-isometric (rigid bones; the joints stretch: mean edge change
  // 3.6% for this biped pose). Measured (Chamfer after ICP; form RMS radius ~90 lbo, ~76 diffusion): biped
  // pose 0 vs pose 1 1.51 (lbo), 0.68 (diffusion); biped vs quadruped 19.5, 15.2. Classical MDS: 1.63, 12.0.
  ArticulatedOptions ao;
  ao.poses = 2;
  ao.seed = 3;
  ao.rest.target_vertices = 900;
  const ArticulatedClass biped = generate_articulated("biped", ao);
  const ArticulatedClass quadruped = generate_articulated("quadruped", ao);
  for (const char* method : {"lbo", "diffusion"}) {
    SCOPED_TRACE(method);
    CanonicalFormOptions o;
    o.method = method;
    const Points a = canonical_form(biped.poses[0], o).X, b = canonical_form(biped.poses[1], o).X;
    const Points other = canonical_form(quadruped.poses[0], o).X;
    const double rms = std::sqrt((a.rowwise() - a.colwise().mean()).rowwise().squaredNorm().mean());
    const double same = aligned_shape_distance(a, b).chamfer, different = aligned_shape_distance(a, other).chamfer;
    EXPECT_LT(same, 0.03 * rms);
    EXPECT_LT(same, 0.2 * different);
  }
}

TEST(SpectralMds, IsClassicalMdsFromAFewGeodesicRows) {
  // Aflalo & Kimmel's spectral MDS (k = 40 eigenfunctions, 120 heat-geodesic rows) against classical MDS of
  // all-pairs heat geodesics on the same 900-vertex biped: the same form up to the area weighting.
  ArticulatedOptions ao;
  ao.poses = 1;
  ao.seed = 3;
  ao.rest.target_vertices = 900;
  const Mesh biped = generate_articulated("biped", ao).poses[0];
  CanonicalFormOptions o;
  o.geodesics.method = GeodesicMethod::Heat;
  o.method = "cmds";
  const Points full = canonical_form(biped, o).X;
  o.method = "spectral-mds";
  const CanonicalForm spectral = canonical_form(biped, o);
  const double rms = std::sqrt((full.rowwise() - full.colwise().mean()).rowwise().squaredNorm().mean());
  const ShapeDistance d = aligned_shape_distance(spectral.X, full);
  EXPECT_LT(d.chamfer, 0.03 * rms);
  const nlohmann::json s = form_summary_json(spectral);
  EXPECT_EQ(s["sources"], 120);
  EXPECT_LT(s["fit_residual"].get<double>(), 0.1);
  // Fewer sources than eigenfunctions cannot fit the basis.
  o.spectral_mds.sources = 20;
  EXPECT_THROW(canonical_form(biped, o), Error);
}

TEST(SpectralMds, AMeshNoLargerThanItsBasisIsRefusedNamingTheBasisAndTheWayOn) {
  // icosphere(1): 42 vertices; a basis of 40 fits, one of 42 needs more vertices than the mesh has.
  CanonicalFormOptions o;
  o.method = "spectral-mds";
  o.spectral_mds.sources = 42;
  EXPECT_TRUE(canonical_form(icosphere(1), o).X.allFinite());
  o.spectral_mds.laplacian.eigenpairs = 42;
  try {
    canonical_form(icosphere(1), o);
    ADD_FAILURE() << "a basis of 42 on 42 vertices was accepted";
  } catch (const Error& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find("basis of 42"), std::string::npos) << what;
    EXPECT_NE(what.find("this mesh has 42"), std::string::npos) << what;
    EXPECT_NE(what.find("method cmds"), std::string::npos) << what;
  }
}

TEST(SpectralForms, BitIdenticalForAnyThreadCount) {
  // The paper experiment's CLI and C++ runs differed in spectral-mds's last bits: Eigen's parallel products
  // block by the thread count. A 900-vertex biped takes the shift-invert path (above kDenseEigenVertices).
  ArticulatedOptions ao;
  ao.poses = 1;
  ao.seed = 5;
  ao.rest.target_vertices = 900;
  const Mesh biped = generate_articulated("biped", ao).poses[0];
  ASSERT_GT(biped.num_vertices(), kDenseEigenVertices);
  const int before = omp_get_max_threads();
  for (const char* method : {"lbo", "diffusion", "spectral-mds"}) {
    CanonicalFormOptions o;
    o.method = method;
    std::vector<Points> runs;
    for (int threads : {1, 2, 3}) {
      omp_set_num_threads(threads);
      runs.push_back(canonical_form(biped, o).X);
    }
    omp_set_num_threads(before);
    for (size_t k = 1; k < runs.size(); ++k) EXPECT_EQ(runs[k], runs[0]) << method << ", threads " << k + 1;
  }
}

TEST(SpectralForms, FormsScaleWithTheShapeAndDiffusionTimeIsScaleFree) {
  const Mesh mesh = bent_strip();  // simple eigenvalues: the eigenvectors are set up to sign
  Mesh big = mesh;
  big.V *= 3;
  for (const char* method : {"lbo", "diffusion"}) {
    CanonicalFormOptions o;
    o.method = method;
    const CanonicalForm small_form = canonical_form(mesh, o), big_form = canonical_form(big, o);
    const double extent = (small_form.X.colwise().maxCoeff() - small_form.X.colwise().minCoeff()).maxCoeff();
    // Up to each axis's sign (on a symmetric shape the largest entry that fixes it can tie).
    for (int c = 0; c < 3; ++c) {
      const double sign = big_form.X.col(c).dot(small_form.X.col(c)) >= 0 ? 1 : -1;
      EXPECT_LT((big_form.X.col(c) - 3 * sign * small_form.X.col(c)).cwiseAbs().maxCoeff(), 1e-6 * 3 * extent)
          << method << " axis " << c;
    }
  }
}

TEST(SpectralForms, DiffusionDistancesMatchTheSumOverAllEigenpairs) {
  // Brute force: d_t(x, y)² = Σ_{i≥1} e^{−2λ_i t} (φ_i(x) − φ_i(y))² over all n eigenpairs of the dense
  // solver; the embedding: the diffusion map of the k = 40 smallest by shift-invert Lanczos.
  const Mesh mesh = torus(40, 16);
  const LaplacianMatrices A = cotangent_laplacian(mesh);
  const LaplaceBeltramiEigen all = laplace_beltrami_eigen_dense(A);
  const LaplaceBeltramiEigen some = laplace_beltrami_eigen(A, with_eigenpairs(40));
  const double t = diffusion_time(some, 1.0);
  const Eigen::MatrixXd Psi = diffusion_map(some, t, 39);
  const Index n = mesh.num_vertices();
  double worst = 0, largest = 0;
  for (Index x = 0; x < n; x += 7)
    for (Index y = 0; y < n; ++y) {
      double reference = 0;
      for (Index i = 1; i < n; ++i)
        reference += std::exp(-2 * all.values[i] * t) * std::pow(all.vectors(x, i) - all.vectors(y, i), 2);
      const double embedded = (Psi.row(x) - Psi.row(y)).norm();
      worst = std::max(worst, std::abs(embedded - std::sqrt(reference)));
      largest = std::max(largest, std::sqrt(reference));
    }
  EXPECT_LT(worst, 1e-6 * largest);
  // The form is κ times the first three axes of the diffusion map.
  const Points form = diffusion_embedding(some, t);
  const double kappa = diffusion_form_scale(some, t);
  EXPECT_LT((form - kappa * Psi.leftCols(3)).cwiseAbs().maxCoeff(), 1e-9 * kappa * Psi.cwiseAbs().maxCoeff());
  const double kept = diffusion_energy_kept(some, t);
  EXPECT_GT(kept, 0);
  EXPECT_LE(kept, 1);
}

TEST(SpectralForms, SignFlippedFormsAreAtDistanceZeroAfterIcp) {
  // A form and its per-axis sign flips (the eigenvectors' sign ambiguity) through the distance distmat
  // uses (ICP, then the Hausdorff distance).
  CanonicalFormOptions o;
  o.method = "lbo";
  const CanonicalForm form = canonical_form(torus(40, 16, 1.0, 0.4), o);
  const double extent = (form.X.colwise().maxCoeff() - form.X.colwise().minCoeff()).maxCoeff();
  for (int flips = 1; flips < 8; ++flips) {
    Points flipped = form.X;
    for (int c = 0; c < 3; ++c)
      if (flips & (1 << c)) flipped.col(c) *= -1;
    const ShapeDistance d = aligned_shape_distance(form.X, flipped);
    EXPECT_LT(d.hausdorff, 1e-6 * extent) << "flips " << flips;
  }
}

TEST(SpectralForms, MethodsReportTheirSpectrumAndNearMultiples) {
  for (const char* method : {"lbo", "diffusion"}) {
    CanonicalFormOptions o;
    o.method = method;
    std::vector<std::string> notes;
    o.note = [&](const std::string& line) { notes.push_back(line); };
    const CanonicalForm f = canonical_form(icosphere(3), o);
    const nlohmann::json s = form_summary_json(f);
    EXPECT_EQ(s["laplacian"], "intrinsic-delaunay");
    EXPECT_EQ(s["eigenvalues"].size(), 10u);
    // The sphere's λ1..λ3 and λ4..λ8 (and λ9 with them? no: 10 eigenpairs end inside the l = 3 group).
    EXPECT_EQ(s["near_multiple"][0], nlohmann::json::array({1, 2, 3}));
    bool said = false;
    for (const std::string& line : notes) said = said || line.find("near-multiple") != std::string::npos;
    EXPECT_TRUE(said) << method;
    EXPECT_TRUE(f.X.allFinite());
    // On the sphere the lbo form is the sphere scaled by √(3/2) (up to a rotation): every point at that
    // radius, to the discretisation error.
    if (std::string(method) == "lbo") {
      const Eigen::VectorXd radius = f.X.rowwise().norm();
      EXPECT_NEAR(radius.minCoeff(), std::sqrt(1.5), 0.03);
      EXPECT_NEAR(radius.maxCoeff(), std::sqrt(1.5), 0.03);
    }
  }
}

// The shift-invert eigensolver hears a stop (support/progress.h) around its factorisation too, not only
// before each Lanczos product: it polls more often than it multiplies; a stop at its first poll ends it.
TEST(LaplaceBeltrami, AStopIsHeardAroundTheFactorisation) {
  const LaplacianMatrices A = cotangent_laplacian(torus(40, 16));  // 640 vertices: above kDenseEigenVertices
  LaplaceBeltramiOptions options = with_eigenpairs(10);
  Index polls = 0;
  options.progress = [&](const std::string&, double, double) { ++polls; };
  const LaplaceBeltramiEigen e = laplace_beltrami_eigen(A, options);
  ASSERT_NE(e.solver, "dense");
  EXPECT_GT(polls, e.operator_products);
  options.progress = [&](const std::string&, double, double) { throw Cancelled(); };
  EXPECT_THROW(laplace_beltrami_eigen(A, options), Cancelled);
}

}  // namespace spectral_test
}  // namespace cshapes
