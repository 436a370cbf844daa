// The benchmarks (experiments/bench_*.h) on tiny inputs: known answers and invariants of what they report —
// the fast sum's error within its stated accuracy, ratios that are the quotients of the times reported, the
// sizes and counts of what was measured, anchors that are missing reported as skipped with the reason.
// Never a speed: the timings of a shared test machine are not a property of the code.
#include <gtest/gtest.h>

#include <algorithm>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <set>

#include "cshapes/mesh/io.h"
#include "cshapes/data/synthetic.h"
#include "cshapes/experiments/bench_coulomb.h"
#include "cshapes/experiments/bench_coulomb_iteration.h"
#include "cshapes/experiments/bench_form.h"
#include "cshapes/experiments/bench_geodesics.h"
#include "cshapes/experiments/bench_icp.h"
#include "cshapes/experiments/bench_smacof.h"
#include "cshapes/experiments/bench_support.h"
#include "cshapes/experiments/figures.h"
#include "cshapes/pipeline/canonical_form_methods.h"
#include "tests/test_support.h"

namespace cshapes {
namespace benchmarks_test {

namespace fs = std::filesystem;

// A positive, finite time.
void expect_time(double seconds, const std::string& what) {
  EXPECT_TRUE(std::isfinite(seconds) && seconds > 0) << what << " = " << seconds;
}

// $CSHAPES_DATA set to `value` for the scope (restored after).
class DataFolder {
 public:
  explicit DataFolder(const std::string& value) {
    if (const char* old = std::getenv("CSHAPES_DATA")) old_ = old, had_ = true;
    setenv("CSHAPES_DATA", value.c_str(), 1);
  }
  ~DataFolder() {
    if (had_)
      setenv("CSHAPES_DATA", old_.c_str(), 1);
    else
      unsetenv("CSHAPES_DATA");
  }

 private:
  std::string old_;
  bool had_ = false;
};

TEST(BenchCoulomb, FastGradientWithinItsAccuracyOfTheCompleteDirectSum) {
  CoulombBenchOptions o;
  o.n = 3000;
  o.distribution = PointDistribution::Clustered;
  o.repeats = 1;
  o.fast_repeats = 2;
  o.accuracy = 1e-3;
  const CoulombBenchResult r = bench_coulomb(o);
  EXPECT_EQ(r.n, 3000);
  EXPECT_EQ(r.distribution, "clustered");
  EXPECT_FALSE(r.direct_extrapolated);
  EXPECT_TRUE(r.direct_float_measured);
  EXPECT_EQ(r.error_targets, r.n);
  EXPECT_GT(r.stats.m2l_interactions, 0) << "the far field must have been approximated";
  EXPECT_GT(r.gradient_rel_error, 0);
  EXPECT_LE(r.gradient_rel_error, o.accuracy);
  EXPECT_LE(r.energy_rel_error, o.accuracy);
  const nlohmann::json j = to_json(r);
  for (const char* time : {"fast_seconds", "direct_seconds", "direct_float_seconds", "fast_cpu_seconds"})
    expect_time(j[time].get<double>(), time);
  EXPECT_DOUBLE_EQ(j["speedup"].get<double>(),
                   j["direct_seconds"].get<double>() / j["fast_seconds"].get<double>());
  EXPECT_DOUBLE_EQ(j["speedup_vs_direct_float"].get<double>(),
                   j["direct_float_seconds"].get<double>() / j["fast_seconds"].get<double>());
  EXPECT_EQ(j["order"], r.stats.order);
  EXPECT_EQ(j["repeats"], 1);
  EXPECT_EQ(j["fast_repeats"], 2);
}

TEST(BenchCoulomb, AboveTheDirectLimitTheErrorIsOverDistinctSampledTargets) {
  CoulombBenchOptions o;
  o.n = 3000;
  o.full_direct_max = 1000;
  o.sample = 200;
  o.repeats = 1;
  o.accuracy = 1e-2;
  const CoulombBenchResult r = bench_coulomb(o);
  EXPECT_TRUE(r.direct_extrapolated);
  EXPECT_FALSE(r.direct_float_measured);
  EXPECT_EQ(r.error_targets, 200);
  EXPECT_GT(r.gradient_rel_error, 0);
  EXPECT_LE(r.gradient_rel_error, o.accuracy);
  const nlohmann::json j = to_json(r);
  EXPECT_TRUE(j["direct_extrapolated"].get<bool>());
  EXPECT_FALSE(j.contains("direct_float_seconds"));
  EXPECT_DOUBLE_EQ(j["speedup"].get<double>(),
                   j["direct_seconds"].get<double>() / j["fast_seconds"].get<double>());
}

TEST(BenchCoulomb, MeshVerticesOrPointsOnItsSurface) {
  const std::string path = test::scratch_dir("bench-coulomb") + "/sphere.off";
  write_mesh(path, icosphere(3));  // 642 vertices
  CoulombBenchOptions o;
  o.mesh = path;
  o.repeats = 1;
  CoulombBenchResult r = bench_coulomb(o);
  EXPECT_EQ(r.n, 642);
  EXPECT_EQ(r.distribution, "mesh-vertices:" + path);
  o.n = 500;
  r = bench_coulomb(o);
  EXPECT_EQ(r.n, 500);
  EXPECT_EQ(r.distribution, "mesh-surface:" + path);
  EXPECT_LE(r.gradient_rel_error, o.accuracy);
}

TEST(BenchCoulombIteration, TorusSizesAndThePapersPowerLaw) {
  // The paper's two figures are the ends of the power law.
  EXPECT_NEAR(paper_coulomb_iteration_seconds(3505), 0.045, 1e-12);
  EXPECT_NEAR(paper_coulomb_iteration_seconds(22738), 0.21, 1e-12);
  CoulombIterationBenchOptions o;
  o.n = 300;
  o.repeats = 3;
  o.windows = 3;
  const CoulombIterationBenchResult r = bench_coulomb_iteration(o);
  EXPECT_EQ(r.source, "torus 30x10");
  // The figure is the median of the windows' medians, each window kept.
  ASSERT_EQ(r.window_seconds.size(), 3u);
  ASSERT_EQ(r.window_seconds_accuracy_1e3.size(), 3u);
  std::vector<double> sorted = r.window_seconds;
  std::sort(sorted.begin(), sorted.end());
  EXPECT_EQ(r.seconds, sorted[1]);
  sorted = r.window_seconds_accuracy_1e3;
  std::sort(sorted.begin(), sorted.end());
  EXPECT_EQ(r.seconds_accuracy_1e3, sorted[1]);
  EXPECT_EQ(r.vertices, 300);
  EXPECT_EQ(r.edges, 3 * r.vertices);  // a closed torus: V − E + F = 0 with F = 2V
  const nlohmann::json j = to_json(r);
  expect_time(j["seconds_per_iteration"].get<double>(), "seconds_per_iteration");
  expect_time(j["seconds_per_iteration_accuracy_1e-3"].get<double>(), "at 1e-3");
  EXPECT_EQ(j["windows"].get<int>(), 3);
  EXPECT_EQ(j["seconds_per_iteration_windows"].get<std::vector<double>>(), r.window_seconds);
  EXPECT_EQ(j["seconds_per_iteration_accuracy_1e-3_windows"].get<std::vector<double>>(),
            r.window_seconds_accuracy_1e3);
  EXPECT_DOUBLE_EQ(j["paper_seconds_per_iteration"].get<double>(), paper_coulomb_iteration_seconds(300));
  EXPECT_DOUBLE_EQ(j["speedup_vs_paper"].get<double>(),
                   j["paper_seconds_per_iteration"].get<double>() / j["seconds_per_iteration"].get<double>());
  EXPECT_DOUBLE_EQ(j["speedup_vs_paper_accuracy_1e-3"].get<double>(),
                   j["paper_seconds_per_iteration"].get<double>() /
                       j["seconds_per_iteration_accuracy_1e-3"].get<double>());
}

TEST(BenchGeodesics, ErrorsAgainstExactGeodesicsAndAnExtrapolatedAnchor) {
  GeodesicsBenchOptions o;
  o.n = 400;
  o.anchor_samples = 8;
  o.exact_samples = 3;
  o.fmm_samples = 8;
  std::vector<std::string> notes;
  o.notes.note = [&](const std::string& line) { notes.push_back(line); };
  const GeodesicsBenchResult r = bench_geodesics(o);
  EXPECT_EQ(r.vertices, 400);  // refined to exactly n
  EXPECT_EQ(r.faces, 2 * r.vertices);
  ASSERT_EQ(notes.size(), 1u);
  EXPECT_NE(notes[0].find("400 vertices"), std::string::npos) << notes[0];
  // Each method within 10% of exact on average (the stress run's tolerance: a broken field is off by tens of
  // percent), and none exactly right.
  for (const GeodesicsBenchMethod* m : {&r.ours, &r.anchor, &r.fmm}) {
    EXPECT_GT(m->mean_relative_error, 0) << m->method;
    EXPECT_LT(m->mean_relative_error, 0.10) << m->method;
    expect_time(m->seconds, m->method);
  }
  EXPECT_TRUE(r.anchor_extrapolated);
  EXPECT_EQ(r.anchor.sampled_sources, 8u);
  EXPECT_EQ(r.fmm.sampled_sources, 8u);
  const std::set<int> sources(r.exact_sources.begin(), r.exact_sources.end());
  EXPECT_EQ(sources.size(), 3u);
  EXPECT_GE(*sources.begin(), 0);
  EXPECT_LT(*sources.rbegin(), 400);
  const nlohmann::json j = to_json(r);
  EXPECT_DOUBLE_EQ(j["speedup_vs_anchor"].get<double>(),
                   j["anchor"]["seconds"].get<double>() / j["ours"]["seconds"].get<double>());
  EXPECT_DOUBLE_EQ(j["cpu_speedup_vs_anchor"].get<double>(),
                   j["anchor"]["cpu_seconds"].get<double>() / j["ours"]["cpu_seconds"].get<double>());
  EXPECT_TRUE(j["anchor"].contains("note"));
  EXPECT_FALSE(j.contains("paper_seconds"));
}

TEST(BenchGeodesics, AnchorOnEverySourceIsNotExtrapolated) {
  GeodesicsBenchOptions o;
  o.n = 200;
  o.anchor_samples = 1000;  // more than n: all n
  o.exact_samples = 1;
  o.fmm_samples = 4;
  const GeodesicsBenchResult r = bench_geodesics(o);
  EXPECT_FALSE(r.anchor_extrapolated);
  EXPECT_EQ(r.anchor.sampled_sources, 200u);
  EXPECT_FALSE(to_json(r)["anchor"].contains("note"));
  o.mesh = "torus.off";  // both a torus (n) and --mesh
  EXPECT_THROW(bench_geodesics(o), Error);
}

IcpBenchOptions small_icp() {
  IcpBenchOptions o;
  o.n = 300;
  o.repeats = 1;
  return o;
}

TEST(BenchIcp, GeneratedBlobsWithoutTheSharedDataAndOpen3dNotAsked) {
  const DataFolder no_data("/nonexistent-cshapes-data");
  IcpBenchOptions o = small_icp();
  o.open3d = false;
  const IcpBenchResult r = bench_icp(o);
  EXPECT_EQ(r.shapes, "generated blobs");
  EXPECT_EQ(r.source_points, 300);
  EXPECT_EQ(r.target_points, 300);
  EXPECT_GE(r.starts, 2u);
  EXPECT_GE(r.iterations_total, r.iterations_all_points);
  // One repeat: the medians are the single run's, and the total is build + align.
  EXPECT_NEAR(r.total_wall_ms, r.build_wall_ms + r.align_wall_ms, 1e-9 * r.total_wall_ms);
  for (double v : {r.rmse, r.hausdorff, r.chamfer, r.no_refine_hausdorff})
    EXPECT_TRUE(std::isfinite(v) && v > 0) << v;
  // A difference of two timed runs: finite, but under load it can come out ≤ 0 (no timing assertions).
  EXPECT_TRUE(std::isfinite(r.ours_ms_per_iteration));
  EXPECT_LE(r.chamfer, r.hausdorff);
  EXPECT_FALSE(r.open3d_measured);
  EXPECT_FALSE(r.open3d_skipped.empty());
  const nlohmann::json j = to_json(r);
  EXPECT_FALSE(j.contains("open3d_ms_per_iteration"));
  EXPECT_FALSE(j.contains("ratio_open3d_over_ours"));
  EXPECT_EQ(j["starts"], r.starts);
}

TEST(BenchIcp, MissingOpen3dIsReportedAsSkippedWithTheReason) {
  const DataFolder no_data("/nonexistent-cshapes-data");
  IcpBenchOptions o = small_icp();
  o.python = "/nonexistent/python3";
  const IcpBenchResult r = bench_icp(o);
  EXPECT_FALSE(r.open3d_measured);
  EXPECT_NE(r.open3d_skipped.find("/nonexistent/python3"), std::string::npos) << r.open3d_skipped;
  const nlohmann::json j = to_json(r);
  EXPECT_TRUE(j["open3d_ms_per_iteration"].is_null());
  EXPECT_EQ(j["open3d_skipped"], r.open3d_skipped);
}

TEST(BenchIcp, RatiosToOpen3dAreTheQuotientsOfTheTimesReported) {
  if (find_python("numpy, open3d").empty()) GTEST_SKIP() << "no Python with Open3D";
  const DataFolder no_data("/nonexistent-cshapes-data");
  const IcpBenchResult r = bench_icp(small_icp());
  ASSERT_TRUE(r.open3d_measured) << r.open3d_skipped;
  EXPECT_FALSE(r.open3d_version.empty());
  const nlohmann::json j = to_json(r);
  expect_time(j["open3d_ms_per_iteration"].get<double>(), "open3d_ms_per_iteration");
  EXPECT_DOUBLE_EQ(j["ratio_open3d_over_ours"].get<double>(),
                   j["open3d_ms_per_iteration"].get<double>() / j["ours_ms_per_iteration"].get<double>());
  EXPECT_DOUBLE_EQ(
      j["ratio_open3d_over_ours_cpu"].get<double>(),
      j["open3d_cpu_ms_per_iteration"].get<double>() / j["ours_cpu_ms_per_iteration"].get<double>());
}

SmacofBenchOptions small_smacof() {
  SmacofBenchOptions o;
  o.n = 200;
  o.iterations = 5;
  return o;
}

TEST(BenchSmacof, StressFallsAndClassicalMdsIsSummarised) {
  SmacofBenchOptions o = small_smacof();
  o.reference = SmacofBenchReference::None;
  std::vector<std::string> notes;
  o.notes.note = [&](const std::string& line) { notes.push_back(line); };
  const SmacofBenchResult r = bench_smacof(o);
  EXPECT_EQ(r.n, 200);
  EXPECT_LT(r.normalized_stress_end, r.normalized_stress_start);  // SMACOF's stress never rises
  EXPECT_GE(r.cmds_eigenvalues[0], r.cmds_eigenvalues[1]);
  EXPECT_GE(r.cmds_eigenvalues[1], r.cmds_eigenvalues[2]);
  EXPECT_GT(r.cmds_explained_energy, 0.99);  // the unrolled Swiss roll is flat: two dimensions hold it
  EXPECT_LE(r.cmds_explained_energy, 1 + 1e-12);
  expect_time(r.seconds_per_iteration, "seconds_per_iteration");
  EXPECT_GT(r.peak_rss_mb, 0);
  EXPECT_FALSE(r.reference_measured);
  EXPECT_FALSE(r.reference_skipped.empty());
  EXPECT_FALSE(notes.empty());
  const nlohmann::json j = to_json(r);
  EXPECT_EQ(j["reference"]["skipped"], r.reference_skipped);
  EXPECT_EQ(j["reference"]["name"], "sklearn.manifold.smacof");
  EXPECT_FALSE(j.contains("speedup_vs_reference"));
  EXPECT_FALSE(j.contains("acceleration"));
  EXPECT_FALSE(j.contains("paper_seconds_per_iteration"));
  EXPECT_EQ(j.contains("single_thread"), r.threads > 1);
  EXPECT_EQ(r.rounds, o.rounds) << "without a reference, ours still runs every round";
  EXPECT_EQ(j["rounds"], o.rounds);
}

TEST(BenchSmacof, MissingScikitLearnIsReportedAsSkippedWithTheReason) {
  SmacofBenchOptions o = small_smacof();
  o.python = "/nonexistent/python3";
  const SmacofBenchResult r = bench_smacof(o);
  EXPECT_FALSE(r.reference_measured);
  EXPECT_NE(r.reference_skipped.find("/nonexistent/python3"), std::string::npos) << r.reference_skipped;
  EXPECT_EQ(to_json(r)["reference"]["skipped"], r.reference_skipped);
}

TEST(BenchSmacof, ScikitLearnReachesTheSameStressFromTheSameStart) {
  if (find_python("numpy, sklearn.manifold").empty()) GTEST_SKIP() << "no Python with scikit-learn";
  SmacofBenchOptions o = small_smacof();
  o.rounds = 2;
  const SmacofBenchResult r = bench_smacof(o);
  ASSERT_TRUE(r.reference_measured) << r.reference_skipped;
  EXPECT_EQ(r.reference_iterations, 5);
  EXPECT_EQ(r.rounds, 2);
  EXPECT_EQ(r.reference_rounds, 2) << "the two sides take turns";
  // Same matrix, same start, same number of Guttman transforms: the same stress, to float rounding.
  EXPECT_GE(r.reference_stress_relative_difference, 0);
  EXPECT_LT(r.reference_stress_relative_difference, 1e-5);
  const nlohmann::json j = to_json(r);
  EXPECT_EQ(j["reference"]["rounds"], 2);
  EXPECT_DOUBLE_EQ(
      j["speedup_vs_reference"].get<double>(),
      j["reference"]["seconds_per_iteration"].get<double>() / j["seconds_per_iteration"].get<double>());
  EXPECT_DOUBLE_EQ(j["cpu_speedup_vs_reference"].get<double>(),
                   j["reference"]["cpu_seconds_per_iteration"].get<double>() /
                       j["cpu_seconds_per_iteration"].get<double>());
}

TEST(BenchSmacof, AcceleratedRunsReachThePlainStressInFewerPasses) {
  // A torus's geodesics (classical MDS of the flat Swiss roll would already be exact: nothing to accelerate).
  SmacofBenchOptions o = small_smacof();
  o.mesh = test::scratch_dir("bench-smacof") + "/torus.off";
  write_mesh(o.mesh, torus(24, 10, 1.0, 0.4));
  o.reference = SmacofBenchReference::None;
  o.acceleration = true;
  o.tolerance = 1e-6;
  const SmacofBenchResult r = bench_smacof(o);
  ASSERT_TRUE(r.acceleration_measured);
  EXPECT_EQ(r.n, 240);
  EXPECT_EQ(r.matrix, o.mesh + " (fmm geodesics)");
  ASSERT_GT(r.plain.iterations, 10);
  const nlohmann::json j = to_json(r)["acceleration"];
  for (const char* method : {"rre", "mpe"}) {
    const SmacofBenchRun& run = std::string(method) == "rre" ? r.rre : r.mpe;
    EXPECT_EQ(run.stop_reason, "target stress") << method;
    EXPECT_LE(run.normalized_stress, r.plain.normalized_stress) << method;
    EXPECT_LE(run.iterations, r.plain.iterations) << method;
    EXPECT_DOUBLE_EQ(j[method]["iteration_ratio"].get<double>(),
                     double(j["none"]["iterations"].get<int>()) / j[method]["iterations"].get<int>());
  }
}

TEST(BenchSupport, AnchorScriptGetsItsFolderInputsAndQuotedArguments) {
  const std::string python = find_python("sys");
  if (python.empty()) GTEST_SKIP() << "no Python";
  AnchorScript s;
  s.package = "the standard library";
  s.imports = "sys";
  s.python = python;
  s.source = "import sys\nprint(open(sys.argv[1] + '/in.txt').read() + ' ' + sys.argv[2])\n";
  s.arguments = {"it's here; $HOME"};
  std::string folder;
  s.write_inputs = [&](const std::string& f) {
    folder = f;
    test::write_text(f + "/in.txt", "input");
  };
  const AnchorRun run = run_python_anchor(s);
  ASSERT_TRUE(run.ran) << run.skipped;
  EXPECT_EQ(run.output, "input it's here; $HOME\n");
  EXPECT_FALSE(folder.empty());
  EXPECT_FALSE(fs::exists(folder)) << "the temporary folder is removed";
}

TEST(BenchSupport, FailingOrMissingAnchorSaysWhy) {
  const std::string python = find_python("sys");
  if (python.empty()) GTEST_SKIP() << "no Python";
  AnchorScript s;
  s.package = "nothing";
  s.imports = "sys";
  s.python = python;
  s.source = "import sys\nprint('partial')\nsys.stderr.write('first\\nthe reason\\n')\nsys.exit(3)\n";
  AnchorRun run = run_python_anchor(s);
  EXPECT_FALSE(run.ran);
  EXPECT_TRUE(run.output.empty());
  EXPECT_NE(run.skipped.find("exit status 3"), std::string::npos) << run.skipped;
  EXPECT_NE(run.skipped.find("the reason"), std::string::npos) << run.skipped;
  s.python = "";
  s.imports = "cshapes_no_such_module_42";
  run = run_python_anchor(s);
  EXPECT_FALSE(run.ran);
  EXPECT_NE(run.skipped.find("cshapes_no_such_module_42"), std::string::npos) << run.skipped;
}

TEST(BenchSupport, SharedToscaShapeFromTheDataFolder) {
  const std::string dir = test::scratch_dir("bench-data");
  test::write_text(dir + "/tosca5k/cat0.off", "OFF\n0 0 0\n");
  const DataFolder data(dir);
  EXPECT_EQ(shared_tosca5k_shape("cat0"), dir + "/tosca5k/cat0.off");
  EXPECT_EQ(shared_tosca5k_shape("cat1"), "");
}

TEST(FormBench, ReportsOneFormOfEachMethodAgainstFullClassicalMds) {
  FormBenchOptions o;
  o.n = 600;  // above the dense eigensolver's limit: shift-invert Lanczos
  o.repeats = 1;
  for (const CanonicalFormMethod& method : canonical_form_method_registry()) {
    o.method = method.name;
    const FormBenchResult r = bench_form(o);
    EXPECT_NEAR(static_cast<double>(r.vertices), 600, 30);
    EXPECT_GT(r.seconds, 0) << method.name;
    EXPECT_GE(r.precompute_seconds, 0) << method.name;
    EXPECT_LE(r.precompute_seconds, r.seconds) << method.name;
    EXPECT_EQ(r.quality.rfind("ok", 0), 0u) << method.name << ": " << r.quality;
    EXPECT_GE(r.peak_rss_mb, r.rss_before_mb);
    ASSERT_TRUE(r.reference_ran) << r.reference_skipped;
    EXPECT_GT(r.reference_seconds, 0);
    EXPECT_GE(r.reference_peak_rss_mb, r.peak_rss_mb);
    const nlohmann::json j = to_json(r);
    EXPECT_EQ(j["method"], method.name);
    EXPECT_DOUBLE_EQ(j["speedup_vs_reference"].get<double>(), r.reference_seconds / r.seconds);
  }
  // The spectral methods say how they solved; landmark MDS says it used landmarks.
  o.method = "lbo";
  EXPECT_NE(bench_form(o).details.value("solver", std::string()).find("shift-invert"), std::string::npos);
  o.method = "cmds";
  o.mds_solver = "landmarks";
  o.reference = false;
  const FormBenchResult landmarks = bench_form(o);
  EXPECT_FALSE(landmarks.reference_ran);
  EXPECT_NE(landmarks.reference_skipped.find("--reference none"), std::string::npos);
  EXPECT_FALSE(to_json(landmarks).contains("speedup_vs_reference"));
  // A solver for a method without one, and an unknown method, are refused.
  o.method = "lbo";
  EXPECT_THROW(bench_form(o), Error);
  o.method = "nonexistent";
  o.mds_solver.clear();
  EXPECT_THROW(bench_form(o), Error);
}

}  // namespace benchmarks_test
}  // namespace cshapes
