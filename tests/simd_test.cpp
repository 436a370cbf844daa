// support/simd.h: the kernels compiled per instruction set. Every target this CPU supports is run here: each
// is deterministic (the same bytes for 1, 2 and 3 threads), and the targets agree with the baseline as
// docs/benchmarks.md states: the Coulomb sums, the metric projection and the forms of every method but SMACOF
// to the byte; the SMACOF pass to 1e-5 of the configuration's size (float pair terms with a 23-bit
// reciprocal square root against an exact one) and its forms after the rigid fit to 0.1% of the diagonal;
// the paper experiment's retrieval figures identical to 3 decimals.
#include <gtest/gtest.h>
#include <omp.h>

#include <cmath>
#include <cstdlib>
#include <cstring>
#include <string>
#include <vector>

#include "cshapes/canon/coulomb_energy.h"
#include "cshapes/canon/coulomb_fmm.h"
#include "cshapes/canon/metric_projection.h"
#include "cshapes/canon/smacof.h"
#include "cshapes/data/articulated.h"
#include "cshapes/data/synthetic.h"
#include "cshapes/experiments/paper_experiment.h"
#include "cshapes/geodesics/geodesics.h"
#include "cshapes/mesh/mesh.h"
#include "cshapes/mesh/rigid_transform.h"
#include "cshapes/pipeline/canonical_forms.h"
#include "cshapes/support/error.h"
#include "cshapes/support/simd.h"
#include "test_support.h"

namespace cshapes {
namespace simd_test {

// Runs f under each supported target, restoring the target chosen before.
template <class F>
void for_each_target(F&& f) {
  const SimdTarget before = simd_target();
  for (SimdTarget t : supported_simd_targets()) {
    set_simd_target(t);
    SCOPED_TRACE(to_string(t));
    f(t);
  }
  set_simd_target(before);
}

// f() evaluated with 1, 2 and 3 threads; every result must have the same bytes as the first.
template <class F>
void expect_same_bytes_for_any_thread_count(F&& f) {
  const int before = omp_get_max_threads();
  omp_set_num_threads(1);
  const Points reference = f();
  for (int threads : {2, 3}) {
    omp_set_num_threads(threads);
    const Points other = f();
    ASSERT_EQ(other.rows(), reference.rows());
    EXPECT_EQ(std::memcmp(other.data(), reference.data(), sizeof(double) * reference.size()), 0)
        << threads << " threads";
  }
  omp_set_num_threads(before);
}

double relative_difference(const Points& a, const Points& b) {
  return (a - b).norm() / b.norm();
}

bool same_bytes(const Points& a, const Points& b) {
  return a.rows() == b.rows() && a.cols() == b.cols() &&
         std::memcmp(a.data(), b.data(), sizeof(double) * a.size()) == 0;
}

// A torus's vertices with one near-duplicate, so the close-pair paths of the near field run too.
Points test_points() {
  Points X = torus(60, 40).V;
  X.row(17) = X.row(16) + Eigen::RowVector3d(1e-9, 2e-9, 0);
  return X;
}

TEST(Simd, NamesParseAndUnknownOnesAreRefusedByName) {
  EXPECT_EQ(parse_simd_target("baseline", "CSHAPES_SIMD"), SimdTarget::Baseline);
  EXPECT_EQ(parse_simd_target("avx2", "CSHAPES_SIMD"), SimdTarget::Avx2);
  EXPECT_EQ(parse_simd_target("avx512", "CSHAPES_SIMD"), SimdTarget::Avx512);
  try {
    parse_simd_target("sse9", "CSHAPES_SIMD");
    FAIL() << "sse9 accepted";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("CSHAPES_SIMD=sse9"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("baseline, avx2 or avx512"), std::string::npos) << e.what();
  }
  const std::vector<SimdTarget> supported = supported_simd_targets();
  ASSERT_FALSE(supported.empty());
  EXPECT_EQ(supported.front(), SimdTarget::Baseline);
  for (SimdTarget t : {SimdTarget::Avx2, SimdTarget::Avx512}) {
    if (!simd_supported(t)) {
      EXPECT_THROW(set_simd_target(t), Error);
    }
  }
}

TEST(Simd, ForcingATargetIsWhatRunsAndIsSaid) {
  for_each_target([](SimdTarget t) {
    EXPECT_EQ(simd_target(), t);
    EXPECT_EQ(simd_description().rfind(to_string(t), 0), 0u) << simd_description();
  });
}

TEST(Simd, CoulombSumsAreDeterministicPerTargetAndTheSameAcrossTargets) {
  const Points X = test_points();
  const CoulombEvaluation exact = coulomb_direct(X);
  CoulombFmmOptions
      fmm;  // the canonization's default accuracy and a tighter one (the exact-difference kernel)
  CoulombFmmOptions tight;
  tight.accuracy = 1e-5;
  Points fmm_baseline, tight_baseline, direct_baseline, exact_baseline;
  for_each_target([&](SimdTarget t) {
    Points fast, precise, direct, reference;
    expect_same_bytes_for_any_thread_count([&] { return reference = coulomb_direct(X).gradient; });
    expect_same_bytes_for_any_thread_count([&] { return fast = coulomb_fmm(X, fmm).gradient; });
    expect_same_bytes_for_any_thread_count([&] { return precise = coulomb_fmm(X, tight).gradient; });
    expect_same_bytes_for_any_thread_count([&] { return direct = coulomb_direct_float(X).gradient; });
    EXPECT_LT(relative_difference(fast, exact.gradient), fmm.accuracy);
    EXPECT_LT(relative_difference(precise, exact.gradient), tight.accuracy);
    EXPECT_LT(relative_difference(direct, exact.gradient), 2e-6);
    if (t == SimdTarget::Baseline) {
      fmm_baseline = fast, tight_baseline = precise, direct_baseline = direct, exact_baseline = reference;
    } else {
      EXPECT_TRUE(same_bytes(reference, exact_baseline)) << relative_difference(reference, exact_baseline);
      EXPECT_TRUE(same_bytes(fast, fmm_baseline)) << relative_difference(fast, fmm_baseline);
      EXPECT_TRUE(same_bytes(precise, tight_baseline)) << relative_difference(precise, tight_baseline);
      EXPECT_TRUE(same_bytes(direct, direct_baseline)) << relative_difference(direct, direct_baseline);
    }
  });
}

TEST(Simd, SmacofPassIsDeterministicPerTargetAndAgreesAcrossTargets) {
  // 700 vertices: three tile blocks, a partial last one, and rows whose remainders are not whole vectors.
  const Mesh mesh = torus(35, 20);
  GeodesicOptions go;
  go.method = GeodesicMethod::FastMarching;
  const DistanceMatrix D = all_pairs_geodesics(mesh, go);
  const Points X0 = mesh.V;
  const Eigen::VectorXd weights = vertex_area_weights(mesh);
  Points uniform_baseline, weighted_baseline, uniform_avx2;
  for_each_target([&](SimdTarget t) {
    Points uniform, weighted;
    expect_same_bytes_for_any_thread_count([&] { return uniform = guttman_transform(D, X0).X_next; });
    expect_same_bytes_for_any_thread_count(
        [&] { return weighted = guttman_transform(D, X0, weights).X_next; });
    if (t == SimdTarget::Avx2) uniform_avx2 = uniform;
    if (t == SimdTarget::Avx512 && uniform_avx2.size() > 0) {  // the AVX2 kernel in AVX-512's registers
      EXPECT_EQ(std::memcmp(uniform.data(), uniform_avx2.data(), sizeof(double) * uniform.size()), 0);
    }
    if (t == SimdTarget::Baseline) {
      uniform_baseline = uniform, weighted_baseline = weighted;
    } else {
      EXPECT_LT(relative_difference(uniform, uniform_baseline), 1e-5);
      EXPECT_LT(relative_difference(weighted, weighted_baseline), 1e-5);
    }
  });
}

TEST(Simd, MetricProjectionIsDeterministicPerTargetAndTheSameAcrossTargets) {
  const Mesh mesh = icosphere(4);
  const Edges E = mesh_edges(mesh.F);
  Eigen::VectorXd rest(E.rows());
  for (Index e = 0; e < E.rows(); ++e) rest[e] = 1.1 * (mesh.V.row(E(e, 0)) - mesh.V.row(E(e, 1))).norm();
  for (ProjectionNorm norm : {ProjectionNorm::L2, ProjectionNorm::L1}) {
    MetricProjectionOptions o;
    o.norm = norm;
    o.dilation = norm == ProjectionNorm::L1 ? 1.0 : 1.05;
    const MetricProjection projection(mesh.V.rows(), E, rest, o);
    Points baseline;
    for_each_target([&](SimdTarget t) {
      Points projected;
      expect_same_bytes_for_any_thread_count([&] {
        Points X = mesh.V;
        projection.project(X);
        return projected = X;
      });
      if (t == SimdTarget::Baseline)
        baseline = projected;
      else
        EXPECT_TRUE(same_bytes(projected, baseline))
            << to_string(norm) << ": " << relative_difference(projected, baseline);
    });
  }
}

// Every method's form under every target, after the best rigid fit to the baseline's form, on a posed
// generated biped (a body without the symmetries of a torus, which let a form turn freely, and not exactly
// mirror-symmetric: see the next test).
TEST(Simd, FormsOfEveryMethodAgreeAcrossTargets) {
  ArticulatedOptions ao;
  ao.poses = 1;
  ao.seed = 4;
  ao.rest.target_vertices = 800;
  const Mesh mesh = generate_articulated("biped", ao).poses[0];
  const double diagonal = bbox_diagonal(mesh.V);
  for (const std::string method : {"coulomb", "cmds", "smacof", "lbo", "diffusion", "spectral-mds"}) {
    CanonicalFormOptions o;
    o.method = method;
    Points baseline;
    for_each_target([&](SimdTarget t) {
      const Points X = canonical_form(mesh, o).X;
      if (t == SimdTarget::Baseline) {
        baseline = X;
        return;
      }
      if (method != "smacof") {  // the only method whose kernels differ between targets
        EXPECT_TRUE(same_bytes(X, baseline)) << method;
        return;
      }
      EXPECT_LT(aligned_rms(X, baseline, /*allow_reflection=*/false), 1e-3 * diagonal) << method;
    });
  }
}

// An exactly mirror-symmetric input (the biped's rest mesh) starts Coulomb's iteration (the landmark MDS
// start) on a symmetric configuration, which the iteration leaves the way rounding tips it: any last-bit
// difference between the targets would grow there (to 0.3% of the diagonal when the kernels fused
// multiply-adds on AVX2 only), so the forms must be the same to the byte.
TEST(Simd, CoulombFormsOfAMirrorSymmetricInputAreTheSameUnderEveryTarget) {
  RestMeshOptions rest;
  rest.target_vertices = 800;
  const Mesh mesh = articulated_rest_mesh(articulated_skeleton("biped"), rest);
  const double diagonal = bbox_diagonal(mesh.V);
  CanonicalFormOptions o;
  o.method = "coulomb";
  Points baseline;
  for_each_target([&](SimdTarget t) {
    const Points X = canonical_form(mesh, o).X;
    if (t == SimdTarget::Baseline) {
      baseline = X;
      return;
    }
    EXPECT_TRUE(same_bytes(X, baseline))
        << 100 * aligned_rms(X, baseline, /*allow_reflection=*/false) / diagonal
        << "% of the diagonal from the baseline's form";
  });
}

// The paper experiment's retrieval figures on a generated set: the same to 3 decimals under every target.
TEST(Simd, PaperExperimentRetrievalIsTheSameUnderEveryTarget) {
  const std::string dir = test::scratch_dir("simd-paper");
  const std::string data = test::generated_dataset(dir, 2, 3, 400);
  std::map<std::string, PaperReport::Retrieval> baseline;
  for_each_target([&](SimdTarget t) {
    PaperExperimentOptions o;
    o.data = data;
    o.out = dir + "/" + to_string(t);
    o.methods = {"coulomb", "smacof"};
    o.table1 = false;
    o.figures = false;
    o.draw = false;
    o.canon.coulomb.max_iterations = 60;
    const PaperReport r = run_paper_experiment(o);
    for (const auto& [method, m] : r.retrieval) {
      if (t == SimdTarget::Baseline) {
        baseline[method] = m;
        continue;
      }
      const PaperReport::Retrieval& b = baseline.at(method);
      for (auto [ours, theirs] :
           {std::pair{m.map, b.map}, {m.nn, b.nn}, {m.ft, b.ft}, {m.st, b.st}, {m.e, b.e}, {m.dcg, b.dcg}})
        EXPECT_EQ(std::lround(ours * 1000), std::lround(theirs * 1000)) << method;
    }
  });
}

}  // namespace simd_test
}  // namespace cshapes
