#include "cshapes/experiments/geodesic_stress.h"

#include <gtest/gtest.h>

#include <cstdio>

namespace cshapes {
namespace geodesic_stress_test {

// A seeded sample of the stress corpus (scripts/stress_geodesics.py runs any number): one mesh of every
// kind at 200-1,200 vertices through every geodesic method against exact geodesics, the canonical forms on
// the smaller ones, and ICP. Every check of experiments/geodesic_stress.h must hold on every mesh.
TEST(GeodesicStress, SeededSampleHasNoFailure) {
  StressCorpusOptions corpus;
  corpus.min_vertices = 200;
  corpus.max_vertices = 1200;
  GeodesicStressOptions options;
  options.canon_max_vertices = 600;
  options.sources = 2;
  for (Index i = 0; i < kStressKinds; ++i) {
    const StressCase c = stress_case(2026, i, corpus);
    const StressCaseResult r = run_stress_case(c, make_stress_mesh(c, corpus), options);
    const nlohmann::json j = stress_result_json(r);
    EXPECT_FALSE(r.failed()) << j.dump(1);
    ASSERT_EQ(r.geodesics.size(), options.geodesic_methods.size());
    for (const StressOutcome& o : r.geodesics) {
      if (o.refused.empty() && o.ran) {
        EXPECT_GE(o.mean_error, 0.0) << o.what;
      }
      // Only CGAL's methods refuse, and only meshes with zero-area faces.
      if (!o.refused.empty()) {
        EXPECT_TRUE(o.what == "exact" || o.what == "heat-cgal") << o.what;
      }
      if (c.kind == StressKind::NearDegenerate && o.what == "exact") {
        EXPECT_FALSE(o.refused.empty());
      }
    }
    std::printf("%s: %lld vertices, heat %.2f%%, fmm %.2f%%, %.1f s\n", c.describe().c_str(),
                static_cast<long long>(r.vertices), 100 * r.geodesics[0].mean_error,
                100 * r.geodesics[3].mean_error, r.seconds);
  }
}

// The checks can fail: an impossible tolerance makes the same mesh fail, and says why.
TEST(GeodesicStress, ATooStrictReferenceIsReported) {
  StressCorpusOptions corpus;
  corpus.min_vertices = 300;
  corpus.max_vertices = 300;
  GeodesicStressOptions options;
  options.geodesic_methods = {"graph"};  // 5-10% long on any triangulation: beyond exact's tolerance
  options.canon = false;
  options.icp = false;
  const StressCase c = stress_case(1, 0, corpus);
  StressCaseResult r = run_stress_case(c, make_stress_mesh(c, corpus), options);
  ASSERT_EQ(r.geodesics.size(), 1u);
  EXPECT_GT(r.geodesics[0].mean_error, geodesic_tolerance("exact"));
  EXPECT_FALSE(r.geodesics[0].failed);  // graph's own tolerance is 25%
  EXPECT_LT(r.geodesics[0].mean_error, geodesic_tolerance("graph"));
}

}  // namespace geodesic_stress_test
}  // namespace cshapes
