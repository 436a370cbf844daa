// pipeline/shape_failures.h: one shape's canonical forms turned into a failure record instead of an error
// (the method named, every method dropped), strict and the run's own I/O errors rethrown, and the geodesic
// fallback of pipeline/canonical_forms.h (heat → fast marching) recorded, also when read from the cache.
// Failures are injected through set_geodesics_test_hook and an option the Coulomb solver refuses.
#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include "cshapes/support/error.h"
#include "cshapes/data/synthetic.h"
#include "cshapes/pipeline/canonical_forms.h"
#include "cshapes/pipeline/shape_failures.h"
#include "test_support.h"

namespace cshapes {
namespace shape_failures_test {

// Clears the hook whatever the test's outcome.
struct HookGuard {
  explicit HookGuard(std::function<void(GeodesicMethod, const std::string&)> hook) {
    set_geodesics_test_hook(std::move(hook));
  }
  ~HookGuard() { set_geodesics_test_hook({}); }
};

std::vector<CanonicalFormOptions> mds_options(const std::string& name) {
  CanonicalFormOptions base;
  base.geodesics.method = GeodesicMethod::Heat;
  return options_per_method(base, {"cmds", "smacof"}, name);
}

TEST(ShapeFailures, HeatFailureFallsBackToFastMarchingAndIsRecorded) {
  const Mesh sphere = icosphere(2);
  const DiskCache cache(test::scratch_dir("shape_failures_fallback"));
  std::vector<GeodesicMethod> asked;
  HookGuard guard([&](GeodesicMethod method, const std::string& name) {
    asked.push_back(method);
    if (method == GeodesicMethod::Heat) fail(name, ": heat: injected failure");
  });
  std::vector<ShapeFailure> failures;
  auto forms = shape_canonical_forms(cache, sphere, mds_options("ball.off"), "ball", failures);
  ASSERT_TRUE(forms.has_value());
  // One shared matrix: heat once, then fast marching once, for both MDS methods.
  ASSERT_EQ(asked.size(), 2u);
  EXPECT_EQ(asked[0], GeodesicMethod::Heat);
  EXPECT_EQ(asked[1], GeodesicMethod::FastMarching);
  ASSERT_EQ(failures.size(), 1u);  // one record per shape and fallback, not per method
  EXPECT_FALSE(failures[0].left_out());
  EXPECT_EQ(failures[0].name, "ball");
  EXPECT_NE(failures[0].fallback.find("injected failure"), std::string::npos) << failures[0].fallback;
  EXPECT_NE(failures[0].fallback.find("fmm instead"), std::string::npos) << failures[0].fallback;
  EXPECT_EQ(count_left_out(failures), 0);
  for (const CachedForm& f : *forms) {
    EXPECT_EQ(f.form.X.rows(), sphere.num_vertices());
    EXPECT_TRUE(f.form.X.allFinite());
    EXPECT_EQ(f.form.geodesics_fallback, failures[0].fallback);
    EXPECT_EQ(form_summary_json(f.form).value("geodesics_fallback", ""),
              failures[0].fallback);
  }
  // The forms are those of fast marching asked for directly.
  CanonicalFormOptions fmm;
  fmm.method = "cmds";
  fmm.geodesics.method = GeodesicMethod::FastMarching;
  const CanonicalForm direct = canonical_form(sphere, fmm);
  EXPECT_LT(((*forms)[0].form.X - direct.X).cwiseAbs().maxCoeff(), 1e-9);

  // A rerun reads both forms from the cache and still says they fell back.
  asked.clear();
  failures.clear();
  forms = shape_canonical_forms(cache, sphere, mds_options("ball.off"), "ball", failures);
  ASSERT_TRUE(forms.has_value());
  EXPECT_TRUE(asked.empty());
  EXPECT_TRUE((*forms)[0].cached);
  ASSERT_EQ(failures.size(), 1u);
  EXPECT_FALSE(failures[0].left_out());
}

TEST(ShapeFailures, StrictHasNoFallback) {
  HookGuard guard([](GeodesicMethod method, const std::string& name) {
    if (method == GeodesicMethod::Heat) fail(name, ": heat: injected failure");
  });
  std::vector<CanonicalFormOptions> options = mds_options("ball.off");
  for (CanonicalFormOptions& o : options) o.strict = true;
  std::vector<ShapeFailure> failures;
  EXPECT_THROW(shape_canonical_forms(DiskCache(""), icosphere(2), options, "ball", failures), Error);
  EXPECT_TRUE(failures.empty());
}

TEST(ShapeFailures, AShapeEveryGeodesicMethodFailsOnIsLeftOutNamingTheMethod) {
  HookGuard guard([](GeodesicMethod method, const std::string& name) {
    fail(name, ": ", to_string(method), ": injected failure");
  });
  CanonicalFormOptions base;
  base.geodesics.method = GeodesicMethod::Heat;
  base.coulomb.max_iterations = 20;
  std::vector<ShapeFailure> failures;
  const auto forms = shape_canonical_forms(
      DiskCache(""), icosphere(2), options_per_method(base, {"coulomb", "cmds", "smacof"}, "ball.off"),
      "ball", failures);
  EXPECT_FALSE(forms.has_value());  // Coulomb's form was fine, but the shape is dropped for every method
  ASSERT_EQ(failures.size(), 1u);
  const ShapeFailure& f = failures[0];
  EXPECT_TRUE(f.left_out());
  EXPECT_EQ(f.name, "ball");
  EXPECT_EQ(f.path, "ball.off");
  EXPECT_EQ(f.method, "cmds");
  EXPECT_EQ(f.stage, "canonical form");
  EXPECT_NE(
      f.reason.find("heat geodesics failed (ball.off: heat: injected failure), and so did fmm (ball.off: "
                    "fmm: injected failure)"),
      std::string::npos)
      << f.reason;
  EXPECT_EQ(count_left_out(failures), 1);
  EXPECT_NE(describe(f).find("ball left out: the cmds canonical form failed"), std::string::npos)
      << describe(f);
  const nlohmann::json j = shape_failures_json(failures);
  ASSERT_EQ(j.size(), 1u);
  EXPECT_EQ(j[0]["method"], "cmds");
  EXPECT_TRUE(j[0]["left_out"].get<bool>());
  EXPECT_TRUE(j[0]["fallback"].is_null());
  const std::string md = shape_failures_markdown(failures);
  EXPECT_NE(md.find("## Shapes left out"), std::string::npos) << md;
  EXPECT_NE(md.find("| ball | `ball.off` | cmds |"), std::string::npos) << md;
}

TEST(ShapeFailures, TheFirstMethodThatFailsIsNamed) {
  // A Coulomb option its solver refuses: the first method fails, the others are not tried.
  CanonicalFormOptions base;
  base.coulomb.step_factor = -1;
  std::vector<ShapeFailure> failures;
  EXPECT_FALSE(shape_canonical_forms(DiskCache(""), icosphere(1),
                                     options_per_method(base, {"coulomb", "cmds"}, "b.off"), "b", failures));
  ASSERT_EQ(failures.size(), 1u);
  EXPECT_EQ(failures[0].method, "coulomb");
  EXPECT_NE(failures[0].reason.find("step-factor must be a number > 0"), std::string::npos) << failures[0].reason;
  // Under strict the error itself comes out.
  base.strict = true;
  EXPECT_THROW(shape_canonical_forms(DiskCache(""), icosphere(1),
                                     options_per_method(base, {"coulomb", "cmds"}, "b.off"), "b", failures),
               Error);
}

TEST(ShapeFailures, TheRunsOwnIoErrorsAreNeverAShapesFailure) {
  for (int kind = 0; kind < 2; ++kind) {
    HookGuard guard([kind](GeodesicMethod, const std::string& name) {
      if (kind == 0) throw IoError(name + ": cache: disk full (injected)");
      throw FileError(name + ": cannot write (injected)");
    });
    std::vector<ShapeFailure> failures;
    if (kind == 0)
      EXPECT_THROW(shape_canonical_forms(DiskCache(""), icosphere(1), mds_options("b.off"), "b", failures),
                   IoError);
    else
      EXPECT_THROW(shape_canonical_forms(DiskCache(""), icosphere(1), mds_options("b.off"), "b", failures),
                   FileError);
    EXPECT_TRUE(failures.empty());
  }
}

TEST(ShapeFailures, NothingFailedMeansNoReportSection) {
  EXPECT_EQ(shape_failures_markdown({}), "");
  EXPECT_EQ(shape_failures_json({}), nlohmann::json::array());
  std::vector<ShapeFailure> failures;
  CanonicalFormOptions base;  // run to convergence: a form stopped at the iteration cap fails its check
  EXPECT_TRUE(shape_canonical_forms(DiskCache(""), icosphere(1),
                                    options_per_method(base, {"coulomb"}, "b.off"), "b", failures));
  EXPECT_TRUE(failures.empty());
}

}  // namespace shape_failures_test
}  // namespace cshapes

namespace cshapes {
namespace shape_failures_test {

// A form that fails its own quality check (Coulomb with no projection and a huge fixed step: every edge
// stretched far beyond 5×) is kept, and recorded as such: stage "form quality", not left out, in the report.
TEST(ShapeFailures, AFormFailingItsQualityCheckIsKeptAndRecorded) {
  const std::string dir = test::scratch_dir("quality-record");
  const DiskCache cache(dir + "/forms");
  CanonicalFormOptions base;
  base.coulomb.step_rule = CoulombStepRule::Fixed;
  base.coulomb.fixed_step = 1e4;
  base.coulomb.projection.steps = 0;
  base.coulomb.max_iterations = 5;
  base.coulomb.tear_fraction = 0;
  const Mesh sphere = icosphere(2);
  std::vector<ShapeFailure> failures;
  const auto forms = shape_canonical_forms(cache, sphere, options_per_method(base, {"coulomb"}, "ball"), "ball",
                                           failures);
  ASSERT_TRUE(forms.has_value());
  ASSERT_EQ(failures.size(), 1u);
  EXPECT_EQ(failures[0].stage, "form quality");
  EXPECT_EQ(failures[0].method, "coulomb");
  EXPECT_FALSE(failures[0].left_out());
  EXPECT_EQ(count_left_out(failures), 0);
  EXPECT_NE(describe(failures[0]).find("NOT OK"), std::string::npos) << describe(failures[0]);
  EXPECT_NE(shape_failures_markdown(failures).find("its own quality check"), std::string::npos);
  // A good form adds no record.
  std::vector<ShapeFailure> none;
  ASSERT_TRUE(shape_canonical_forms(cache, sphere, options_per_method({}, {"coulomb"}, "ball"), "ball", none));
  EXPECT_TRUE(none.empty()) << describe(none.front());
}

// Issue 36: one shape failing for three methods was reported as "3 shapes were left out".
TEST(ShapeFailures, AShapeFailingForSeveralMethodsCountsOnce) {
  std::vector<ShapeFailure> failures = {{"cat9", "d/cat9.off", "cmds", "canonical form", "x", ""},
                                        {"cat9", "d/cat9.off", "smacof", "canonical form", "x", ""},
                                        {"cat9", "d/cat9.off", "lbo", "canonical form", "x", ""},
                                        {"dog2", "d/dog2.off", "cmds", "geodesics", "y", "fmm instead"}};
  EXPECT_EQ(count_left_out(failures), 1);
  failures.push_back({"dog2", "d/dog2.off", "", "read", "z", ""});
  EXPECT_EQ(count_left_out(failures), 2);
}

}  // namespace shape_failures_test
}  // namespace cshapes
