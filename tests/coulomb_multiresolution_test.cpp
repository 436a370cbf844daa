#include "cshapes/canon/coulomb_multiresolution.h"

#include <gtest/gtest.h>

#include <cstdio>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <random>

#include "cshapes/support/error.h"
#include "cshapes/mesh/io.h"
#include "cshapes/mesh/rigid_transform.h"
#include "cshapes/data/stress_corpus.h"
#include "cshapes/mesh/subdivide.h"
#include "cshapes/data/synthetic.h"
#include "tests/test_support.h"

namespace cshapes {
namespace coulomb_multiresolution_test {

// Points on and near a coarse surface, off it by up to a fifth of an edge.
Points points_near(const Mesh& coarse, Index count, unsigned seed) {
  std::mt19937_64 rng(seed);
  Points P = sample_surface(coarse, count, rng);
  std::normal_distribution<double> normal(0.0, 0.05);
  for (Index i = 0; i < P.rows(); ++i) P.row(i) += Eigen::RowVector3d(normal(rng), normal(rng), normal(rng));
  return P;
}

// Known answers: the identity form carries every point to itself, a rigid motion of the form moves them by
// the same motion, a uniform scaling scales them (normal offsets too: √(area ratio) = the scale).
TEST(CoulombMultiresolution, ProlongationOfAffineFormsIsExact) {
  const Mesh coarse = icosphere(2, 3.0);
  const Points P = points_near(coarse, 500, 4);
  const double scale = 3.0;
  EXPECT_LT((prolong_to_fine(P, coarse.V, coarse.F, coarse.V) - P).cwiseAbs().maxCoeff(), 1e-12 * scale);
  const RigidTransform motion = random_rigid_transform(7, 2.0);
  const Points moved = prolong_to_fine(P, coarse.V, coarse.F, motion.apply(coarse.V));
  EXPECT_LT((moved - motion.apply(P)).cwiseAbs().maxCoeff(), 1e-9 * scale);
  const Points scaled = prolong_to_fine(P, coarse.V, coarse.F, 2.5 * coarse.V);
  EXPECT_LT((scaled - 2.5 * P).cwiseAbs().maxCoeff(), 1e-9 * scale);
}

// At or below above_resolution nothing changes: the single-level iteration's form, bit for bit.
TEST(CoulombMultiresolution, SmallMeshesRunTheSingleLevelIteration) {
  const Mesh m = icosphere(2);
  CoulombCanonOptions options;
  options.max_iterations = 30;
  const CoulombMultiresolutionResult mr = coulomb_multiresolution(m, options);
  EXPECT_FALSE(mr.used);
  const CoulombCanonResult direct = coulomb_canonical_form(m.V, mesh_edges(m.F), options);
  EXPECT_EQ((mr.result.X - direct.X).cwiseAbs().maxCoeff(), 0.0);
}

// A fine mesh through a coarse version of its surface: the form has every fine vertex, passes the quality
// check, and the coarse tears become more fine ones (scaled by the edge-length ratio).
TEST(CoulombMultiresolution, FineMeshThroughCoarse) {
  CapsuleOptions co;
  co.segments = 24;
  co.bend = 2.0;
  const Mesh fine = split_longest_edges(capsule(co), 3000);
  CoulombCanonOptions options;
  options.multiresolution.above_resolution = 1500;
  options.multiresolution.coarse_vertices = 800;
  options.max_iterations = 300;
  options.tear_after = 100;
  const CoulombMultiresolutionResult mr = coulomb_multiresolution(fine, options);
  ASSERT_TRUE(mr.used) << mr.note;
  EXPECT_NEAR(static_cast<double>(mr.coarse_vertices), 800, 16);
  ASSERT_EQ(mr.result.X.rows(), fine.num_vertices());
  EXPECT_TRUE(mr.result.X.allFinite());
  EXPECT_TRUE(mr.result.quality.ok) << mr.result.quality.description;
  EXPECT_GT(mr.coarse_torn_edges, 0);
  const double ratio = static_cast<double>(mr.result.torn_edges.rows()) / mr.coarse_torn_edges;
  EXPECT_GT(ratio, 1.2);  // finer edges: more of them along the same cuts
  EXPECT_EQ(mr.result.torn_vertices.size(), fine.num_vertices());
  EXPECT_FALSE(mr.note.empty());
}

// Two parallel squares 0.1 apart, facing each other (a hand on a thigh): a point 0.06 above the lower one,
// facing up, is nearer the upper square but belongs to the lower. With its normal it follows the lower
// square's form; without, the upper's (moved 10 along x in the form).
TEST(CoulombMultiresolution, ProlongationFollowsTheTriangleFacingThePointsWay) {
  Points Vc(8, 3);
  Vc << 0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0,  // lower, normal +z
      0, 0, 0.1, 1, 0, 0.1, 1, 1, 0.1, 0, 1, 0.1;  // upper, normal -z
  Faces Fc(4, 3);
  Fc << 0, 1, 2, 0, 2, 3, 4, 6, 5, 4, 7, 6;
  Points Yc = Vc;
  Yc.bottomRows(4).col(0).array() += 10.0;
  Points P(1, 3), up(1, 3), down(1, 3);
  P << 0.4, 0.3, 0.06;
  up << 0, 0, 1;
  down << 0, 0, -1;
  EXPECT_LT((prolong_to_fine(P, Vc, Fc, Yc, up) - P).norm(), 1e-12);
  EXPECT_NEAR(prolong_to_fine(P, Vc, Fc, Yc, down)(0, 0), 10.4, 1e-12);
  EXPECT_NEAR(prolong_to_fine(P, Vc, Fc, Yc)(0, 0), 10.4, 1e-12);  // no normals: the nearest
}

// Regressions at 59,727 vertices. KIDS kid3 (an arm near the body): the form failed its quality check with
// 587 vertices on edges stretched up to 700× (wrong-part prolongation and fine edges left across the coarse
// gaps). kid7: 5 vertices on edges stretched 17.8× after the 20 tear rounds there were (it needs 25: the
// rounds after full_rounds, cheaper, finish it). Both pass now.
TEST(CoulombMultiresolution, KidsPosesAtFullResolutionPassTheirQualityCheck) {
  CSHAPES_REQUIRE_DATA();
  for (const char* name : {"kid3", "kid7"}) {
    const std::string path = test::data_dir() + "/kids/" + name + ".off";
    if (!std::filesystem::exists(path)) GTEST_SKIP() << path << " not found";
    const Mesh kid = read_mesh(path);
    const CoulombMultiresolutionResult mr = coulomb_multiresolution(kid, CoulombCanonOptions{});
    ASSERT_TRUE(mr.used) << mr.note;
    EXPECT_TRUE(mr.result.quality.ok) << name << ": " << mr.result.quality.description << "; " << mr.note;
    EXPECT_LT(mr.result.quality.p99_stretch, 3.0) << name;
  }
}

// The switch reads the resolution, not the vertex count: the same 3,000 vertices stretched 4× along the
// capsule's axis (long thin triangles, as in scans) are a coarser triangulation for the step rule, and stay
// at the single level where the even capsule goes through the coarse version.
TEST(CoulombMultiresolution, TheSwitchReadsTheResolution) {
  CapsuleOptions co;
  co.segments = 24;
  const Mesh even = split_longest_edges(capsule(co), 3000);
  Mesh stretched = even;
  Eigen::Index axis;
  (even.V.colwise().maxCoeff() - even.V.colwise().minCoeff()).maxCoeff(&axis);
  stretched.V.col(axis) *= 4.0;
  const double r_even = even_triangulation_vertices(even.V, even.F);
  const double r_stretched = even_triangulation_vertices(stretched.V, stretched.F);
  ASSERT_LT(r_stretched, 0.8 * r_even);
  CoulombCanonOptions options;
  options.multiresolution.above_resolution = static_cast<Index>(std::lround(0.9 * r_even));
  options.multiresolution.coarse_vertices = 800;
  options.max_iterations = 40;
  options.tear_after = 20;
  options.multiresolution.tear_rounds = 1;
  const CoulombMultiresolutionResult a = coulomb_multiresolution(even, options);
  const CoulombMultiresolutionResult b = coulomb_multiresolution(stretched, options);
  EXPECT_TRUE(a.used) << a.note;
  EXPECT_FALSE(b.used) << b.note;
  EXPECT_NE(b.note.find("resolution "), std::string::npos) << b.note;
}

// Options out of their limits are refused; a coarse version no coarser than the mesh is no reason to fail:
// the single-level iteration runs, and the note says why.
TEST(CoulombMultiresolution, RefusesBadOptions) {
  const Mesh m = icosphere(3);
  CoulombCanonOptions options;
  options.max_iterations = 20;
  options.multiresolution.above_resolution = 100;
  options.multiresolution.coarse_vertices = m.num_vertices();
  const CoulombMultiresolutionResult same = coulomb_multiresolution(m, options);
  EXPECT_FALSE(same.used);
  EXPECT_NE(same.note.find("not more than the coarse version"), std::string::npos) << same.note;
  options.multiresolution.coarse_vertices = 3;
  EXPECT_THROW(coulomb_multiresolution(m, options), Error);
  options.multiresolution.coarse_vertices = 200;
  options.multiresolution.above_resolution = -1;
  EXPECT_THROW(coulomb_multiresolution(m, options), Error);
  options.multiresolution.above_resolution = 100;
  options.multiresolution.tear_rounds = -1;
  EXPECT_THROW(coulomb_multiresolution(m, options), Error);
  options.multiresolution.tear_rounds = 100;
  options.multiresolution.full_rounds = -1;
  EXPECT_THROW(coulomb_multiresolution(m, options), Error);
  EXPECT_THROW(prolong_to_fine(m.V, m.V, Faces(0, 3), m.V), Error);
}

// The CLI reaches the multiresolution options: a 3,000-vertex capsule goes through a coarse version when
// above 1,500, runs single level with 0, and a fine-mesh option without multiresolution is refused by name.
TEST(CoulombMultiresolution, CliOptionsChooseThePath) {
  CapsuleOptions co;
  co.segments = 24;
  const std::string dir = test::scratch_dir("multiresolution_cli");
  const std::string mesh = dir + "/capsule.off";
  write_mesh(mesh, split_longest_edges(capsule(co), 3000));
  const std::string common = "-q canon " + mesh + " -o " + dir + "/form.off --method coulomb --json " +
                             "--coulomb-max-iterations 60 --tear-after 30 ";
  auto note_of = [](const test::CliResult& r) {
    EXPECT_EQ(r.exit_code, 0) << r.err;
    const nlohmann::json j = nlohmann::json::parse(r.out);
    return j.dump();
  };
  const std::string multi =
      note_of(test::run_cli(common + "--coulomb-multiresolution-above 1500 --coulomb-coarse-vertices 800 "
                                     "--coulomb-tear-rounds 2"));
  EXPECT_NE(multi.find("coarse"), std::string::npos) << multi;
  const std::string single = note_of(test::run_cli(common + "--coulomb-multiresolution-above 0"));
  EXPECT_NE(single.find("multiresolution off"), std::string::npos) << single;
  const test::CliResult refused =
      test::run_cli(common + "--coulomb-multiresolution-above 0 --coulomb-coarse-vertices 800");
  EXPECT_NE(refused.exit_code, 0);
  EXPECT_NE(refused.err.find("--coulomb-coarse-vertices"), std::string::npos) << refused.err;
}

// A seeded sample of the stress corpus (every kind: jitter, flips, slivers, zero-area faces, thin tubes,
// glued handles, boundaries, scales far from 1) through the multiresolution path, its thresholds lowered so
// that meshes of 1,800-3,000 vertices take it: no case throws, every form is finite, every mesh the remesher
// takes goes through the coarse version (else the note says why), and the form-quality verdicts are printed.
// At the default thresholds the corpus runs by `scripts/stress_geodesics.py --min-vertices 9000 --extra
// "--geodesic-methods heat --exact-max 0 --canon-max 40000 --methods coulomb --no-icp"` (docs/results.md).
TEST(CoulombMultiresolution, StressCorpusSampleThroughTheCoarsePath) {
  StressCorpusOptions corpus;
  corpus.min_vertices = 1800;
  corpus.max_vertices = 3000;
  CoulombCanonOptions options;
  // Below the resolution of every case (uneven kinds come out well below their vertex count: a thin tube of
  // 3-8 vertices around far below), so that each takes the coarse path.
  options.multiresolution.above_resolution = 1;
  options.multiresolution.coarse_vertices = 600;
  options.max_iterations = 150;
  options.tear_after = 60;
  int used = 0, passed = 0, examined = 0;
  for (Index i = 0; i < kStressKinds; ++i) {
    const StressCase c = stress_case(11, i, corpus);
    const Mesh mesh = make_stress_mesh(c, corpus);
    if (even_triangulation_vertices(mesh.V, mesh.F) <= options.multiresolution.above_resolution) continue;
    ++examined;
    SCOPED_TRACE(c.describe());
    CoulombMultiresolutionResult mr;
    ASSERT_NO_THROW(mr = coulomb_multiresolution(mesh, options));
    ASSERT_EQ(mr.result.X.rows(), mesh.num_vertices());
    EXPECT_TRUE(mr.result.X.allFinite());
    EXPECT_FALSE(mr.note.empty());
    used += mr.used;
    passed += mr.result.quality.ok;
    std::printf("%-40s %s | %s\n", c.name().c_str(), mr.used ? "coarse path" : mr.note.c_str(),
                mr.result.quality.description.c_str());
  }
  EXPECT_EQ(examined, kStressKinds);
  EXPECT_GE(used, kStressKinds - 2);  // the remesher may refuse a mesh with zero-area faces or slivers
  std::printf("%d of %d through the coarse path, %d pass the quality check\n", used, kStressKinds, passed);
}

}  // namespace coulomb_multiresolution_test
}  // namespace cshapes
