// cmds and smacof by landmark rows through canonical_form (pipeline/method_mds.cpp): the solver option, the
// auto rule, the memory the distances take (L × n entries, from the form's summary), and the cache key.
#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include "cshapes/mesh/io.h"
#include "cshapes/mesh/rigid_transform.h"
#include "cshapes/data/synthetic.h"
#include "cshapes/pipeline/canonical_form_methods.h"
#include "cshapes/pipeline/canonical_forms.h"
#include "tests/test_support.h"

namespace cshapes {
namespace landmark_forms_test {

double bbox_diagonal(const Points& X) {
  return (X.colwise().maxCoeff() - X.colwise().minCoeff()).norm();
}

CanonicalFormOptions mds_options(const std::string& method, MdsSolver solver, Index landmarks = 120) {
  CanonicalFormOptions o;
  o.method = method;
  o.geodesics.method = GeodesicMethod::Heat;
  o.mds_solver.solver = solver;
  o.mds_solver.landmarks = landmarks;
  return o;
}

nlohmann::json summary_of(const CanonicalForm& form) {
  return form_summary_json(form);
}

// Landmark cmds and smacof through canonical_form: distances of L × n entries (never n × n), forms within 2%
// of the bounding-box diagonal of the full methods' after the best rigid motion or reflection.
TEST(LandmarkForms, LandmarksTakeLTimesNAndAgreeWithTheFullForms) {
  const Mesh m = torus(64, 24, 2.0, 0.7);  // 1,536 vertices
  const Index n = m.num_vertices();
  for (const char* method : {"cmds", "smacof"}) {
    const CanonicalForm full = canonical_form(m, mds_options(method, MdsSolver::Full));
    const CanonicalForm landmarks = canonical_form(m, mds_options(method, MdsSolver::Landmarks));
    const nlohmann::json fs = summary_of(full), ls = summary_of(landmarks);
    EXPECT_EQ(fs["mds_solver"]["solver"], "full");
    EXPECT_EQ(fs["mds_solver"]["distance_entries"].get<Index>(), n * n);
    EXPECT_EQ(ls["mds_solver"]["solver"], "landmarks");
    EXPECT_EQ(ls["mds_solver"]["landmarks"].get<Index>(), 120);
    EXPECT_EQ(ls["mds_solver"]["distance_entries"].get<Index>(), 120 * n);
    ASSERT_EQ(landmarks.X.rows(), n);
    EXPECT_TRUE(landmarks.X.allFinite());
    const double error = aligned_rms(landmarks.X, full.X, true) / bbox_diagonal(full.X);
    EXPECT_LT(error, 0.02) << method;
    EXPECT_TRUE(ls.contains("form_quality")) << method;
    EXPECT_EQ(ls.contains("smacof"), std::string(method) == "smacof");
  }
}

// auto: the full matrix at this size; landmarks once the mesh is above auto_full_max_vertices.
TEST(LandmarkForms, AutoPicksBySize) {
  const Mesh m = torus(24, 10, 2.0, 0.7);  // 240 vertices
  CanonicalFormOptions o = mds_options("cmds", MdsSolver::Auto, 40);
  EXPECT_EQ(summary_of(canonical_form(m, o))["mds_solver"]["solver"], "full");
  EXPECT_FALSE(mds_uses_landmarks(o, m.num_vertices()));
  o.mds_solver.auto_full_max_vertices = 200;
  EXPECT_TRUE(mds_uses_landmarks(o, m.num_vertices()));
  EXPECT_EQ(summary_of(canonical_form(m, o))["mds_solver"]["solver"], "landmarks");
  o.distances_file = "given.bin";  // a given matrix is the full matrix
  EXPECT_FALSE(mds_uses_landmarks(o, m.num_vertices()));
}

// The solver options are in the MDS methods' cache keys and not in Coulomb's.
TEST(LandmarkForms, CacheKeys) {
  CanonicalFormOptions a = mds_options("cmds", MdsSolver::Full),
                       b = mds_options("cmds", MdsSolver::Landmarks);
  EXPECT_NE(canonical_form_key(a), canonical_form_key(b));
  b.mds_solver.solver = MdsSolver::Full;
  b.mds_solver.landmarks = 7;
  EXPECT_NE(canonical_form_key(a), canonical_form_key(b));
  a.method = b.method = "coulomb";
  EXPECT_EQ(canonical_form_key(a), canonical_form_key(b));
}

// A point cloud: landmark rows of graph distances on its kNN graph.
TEST(LandmarkForms, PointCloud) {
  Mesh cloud;
  cloud.V = torus(40, 16, 2.0, 0.7).V;
  const CanonicalForm form = canonical_form(cloud, mds_options("cmds", MdsSolver::Landmarks, 30));
  EXPECT_EQ(summary_of(form)["mds_solver"]["distance_entries"].get<Index>(), 30 * cloud.num_vertices());
  EXPECT_TRUE(form.X.allFinite());
}

// Landmark SMACOF's fold repair on real data (tosca5k michael0, L = 300, heat rows): without it the
// interpolation leaves vertices across a fold (the form-quality check fails: measured 20 vertices on edges
// stretched up to 33×); with it (the default) the form passes, the points it placed again are said in the
// summary, and the form stays within 1% of the diagonal of the unrepaired one (a few dozen points moved).
TEST(LandmarkForms, SmacofFoldRepairOnTosca) {
  CSHAPES_REQUIRE_DATA();
  const Mesh m = read_mesh(test::tosca5k("michael0"));
  CanonicalFormOptions o = mds_options("smacof", MdsSolver::Landmarks, 300);
  o.mds_solver.fold_overstretch = 0;
  const CanonicalForm folded = canonical_form(m, o);
  const nlohmann::json fs = summary_of(folded);
  EXPECT_FALSE(fs["form_quality"]["ok"].get<bool>()) << fs["form_quality"].dump();
  EXPECT_EQ(fs["smacof"]["fold_repair"]["replaced_points"].get<Index>(), 0);
  o.mds_solver.fold_overstretch = MdsSolverOptions{}.fold_overstretch;
  const CanonicalForm repaired = canonical_form(m, o);
  const nlohmann::json rs = summary_of(repaired);
  EXPECT_TRUE(rs["form_quality"]["ok"].get<bool>()) << rs["form_quality"].dump();
  const Index replaced = rs["smacof"]["fold_repair"]["replaced_points"].get<Index>();
  EXPECT_GT(replaced, 0);
  EXPECT_LT(replaced, m.num_vertices() / 20);
  EXPECT_EQ(rs["smacof"]["fold_repair"]["overstretched_edges_left"].get<Index>(), 0);
  EXPECT_LT(aligned_rms(repaired.X, folded.X, true) / bbox_diagonal(folded.X), 0.01);
}

// A stop (Ctrl-C in Python: a progress callback that throws Cancelled, support/progress.h) is heard in the
// landmark path's set-up (the heat method's factorisations), before the first landmark row is solved: the
// first call the callback gets is a poll, not the report of a finished row.
TEST(LandmarkForms, AStopIsHeardBeforeTheFirstLandmarkRow) {
  const Mesh m = torus(64, 24, 2.0, 0.7);  // 1,536 vertices
  for (const char* method : {"cmds", "smacof"}) {
    CanonicalFormOptions o = mds_options(method, MdsSolver::Landmarks);
    std::string first_stage = "none";
    o.progress = [&](const std::string& stage, double, double) {
      first_stage = stage;
      throw Cancelled();
    };
    EXPECT_THROW(canonical_form(m, o), Cancelled) << method;
    EXPECT_EQ(first_stage, "") << method;
  }
}

}  // namespace landmark_forms_test
}  // namespace cshapes
