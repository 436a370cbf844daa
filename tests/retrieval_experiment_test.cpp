// `cshapes experiment retrieval` (experiments/retrieval_experiment.h) end to end on a tiny collection, and
// --resample (pipeline/resampled_dataset.h): the files, the measures against the matrices, resume, the .cla,
// and the remesh's measures.
#include "cshapes/experiments/retrieval_experiment.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <nlohmann/json.hpp>

#include "cshapes/support/atomic_file.h"
#include "cshapes/support/error.h"
#include "cshapes/data/classification.h"
#include "cshapes/data/dataset.h"
#include "cshapes/mesh/io.h"
#include "cshapes/mesh/remesh.h"
#include "cshapes/data/synthetic.h"
#include "cshapes/eval/distance_csv.h"
#include "cshapes/experiments/figures.h"
#include "cshapes/experiments/noise_experiment.h"
#include "cshapes/experiments/paper_experiment.h"
#include "cshapes/pipeline/resampled_dataset.h"
#include "tests/test_support.h"

namespace cshapes {
namespace retrieval_experiment_test {

namespace fs = std::filesystem;

// Three spheres and three tori of different sizes: two classes of three, about 160 vertices each.
std::string tiny_collection(const std::string& dir) {
  for (int k = 0; k < 3; ++k) {
    write_mesh(dir + "/data/sphere" + std::to_string(k) + ".off", icosphere(2, 1.0 + 0.1 * k));
    write_mesh(dir + "/data/torus" + std::to_string(k) + ".off", torus(16, 10, 1.0 + 0.1 * k, 0.3 + 0.03 * k));
  }
  return dir + "/data";
}

RetrievalExperimentOptions fast_options(const std::string& dir) {
  RetrievalExperimentOptions o;
  o.data = tiny_collection(dir);
  o.out = dir + "/out";
  o.methods = {"cmds"};
  o.canon.geodesics.method = GeodesicMethod::Graph;
  return o;
}

TEST(RetrievalExperiment, EndToEndFilesMeasuresAndResume) {
  const std::string dir = test::scratch_dir("retrieval-experiment");
  RetrievalExperimentOptions o = fast_options(dir);
  const RetrievalExperimentResult r = retrieval_experiment(o);
  EXPECT_EQ(r.shapes, 6);
  EXPECT_EQ(r.class_names, (std::vector<std::string>{"sphere", "torus"}));
  ASSERT_EQ(r.methods.size(), 1u);
  const RetrievalMethodResult& m = r.methods[0];
  EXPECT_EQ(m.forms_computed, 6);
  EXPECT_EQ(m.pairs_computed, 15);
  for (const std::string& kind : retrieval_distances()) {
    // The measures are those of the matrix written, as `cshapes evaluate` would compute them.
    const NamedDistances written = read_distance_csv(o.out + "/cmds/" + kind + ".csv");
    EXPECT_EQ(written.names, m.names);
    const RetrievalResult again = evaluate_retrieval(written.D, {0, 0, 0, 1, 1, 1});
    EXPECT_NEAR(m.by_distance.at(kind).result.mean.ap, again.mean.ap, 1e-12) << kind;
    // The tools' forms hold the same numbers, in the order of cmds/classes.cla.
    const NamedDistances text = read_distance_csv(o.out + "/cmds/" + kind + ".txt");
    EXPECT_TRUE(text.D.isApprox(written.D, 1e-8)) << kind;
    EXPECT_EQ(fs::file_size(o.out + "/cmds/" + kind + ".matrix"), 36u * 4u);
    for (const char* f : {"metrics.json", "pr.csv", "queries.csv", "matrix.csv", "confusion.csv"})
      EXPECT_TRUE(fs::exists(o.out + "/cmds/" + kind + "/" + f)) << kind << "/" << f;
  }
  // Spheres against tori: every method tells them apart.
  EXPECT_EQ(m.by_distance.at("hausdorff").result.mean.nn, 1.0);
  const Classification cla = read_classification(o.out + "/classes.cla");
  ASSERT_EQ(cla.classes.size(), 2u);
  EXPECT_EQ(cla.classes[1].models, (std::vector<std::string>{"torus0", "torus1", "torus2"}));
  EXPECT_EQ(read_classification(o.out + "/cmds/classes.cla").models(), m.names);
  const std::string report = read_text_file(o.out + "/report.md");
  for (const char* part : {"## Overall", "## Per class", "| sphere | 3 |", "## Confusion", "## Files"})
    EXPECT_NE(report.find(part), std::string::npos) << part;
  const nlohmann::json j = nlohmann::json::parse(read_text_file(o.out + "/retrieval.json"));
  EXPECT_EQ(j["methods"][0]["distances"]["hausdorff"]["classes"]["torus"]["queries"], 3);
  if (!find_python("matplotlib, numpy").empty()) {
    EXPECT_EQ(r.figures.size(), 3u) << r.figures_note;
    for (const std::string& f : r.figures) EXPECT_GT(fs::file_size(o.out + "/" + f), 1000u) << f;
  }
  // A rerun computes nothing and gives the same numbers.
  const std::string matrix = read_text_file(o.out + "/cmds/hausdorff.csv");
  o.figures = false;
  const RetrievalExperimentResult again = retrieval_experiment(o);
  EXPECT_EQ(again.methods[0].forms_computed, 0);
  EXPECT_EQ(again.methods[0].pairs_computed, 0);
  EXPECT_EQ(again.methods[0].pairs_cached, 15);
  EXPECT_EQ(read_text_file(o.out + "/cmds/hausdorff.csv"), matrix);
}

// The profile: every stage of every method, in order, with its times; and the same in retrieval.json.
TEST(RetrievalExperiment, ProfileNamesEveryStageWithItsTimes) {
  const std::string dir = test::scratch_dir("retrieval-experiment-profile");
  RetrievalExperimentOptions o = fast_options(dir);
  o.methods = {"cmds", "lbo"};
  o.figures = false;
  const RetrievalExperimentResult r = retrieval_experiment(o);
  std::vector<std::string> stages;
  for (const StageTime& t : r.profile) {
    stages.push_back(t.stage + ":" + t.method);
    EXPECT_GE(t.wall_seconds, 0) << t.stage;
    EXPECT_GE(t.cpu_seconds, 0) << t.stage;
  }
  EXPECT_EQ(stages, (std::vector<std::string>{"forms:cmds", "pairs:cmds", "measures:cmds", "forms:lbo",
                                              "pairs:lbo", "measures:lbo"}));
  double wall = 0;
  for (const StageTime& t : r.profile) wall += t.wall_seconds;
  EXPECT_LE(wall, r.seconds * 1.01 + 1e-3);  // the stages do not overlap
  EXPECT_GE(r.cores, 1);
  const nlohmann::json j = nlohmann::json::parse(read_text_file(o.out + "/retrieval.json"));
  ASSERT_EQ(j["profile"].size(), 6u);
  EXPECT_EQ(j["profile"][1]["stage"], "pairs");
  EXPECT_EQ(j["profile"][1]["method"], "cmds");
  EXPECT_NE(read_text_file(o.out + "/report.md").find("### Where the time went"), std::string::npos);
}

// Classical MDS and SMACOF share each shape's geodesic matrix: computed once, ahead of their passes, and the
// same matrices (to the byte) and counts as runs of each method alone.
TEST(RetrievalExperiment, MdsMethodsShareTheGeodesicMatrixWithTheSameResults) {
  const std::string dir = test::scratch_dir("retrieval-experiment-shared-geodesics");
  RetrievalExperimentOptions o = fast_options(dir);
  o.methods = {"cmds", "smacof"};
  o.figures = false;
  const RetrievalExperimentResult both = retrieval_experiment(o);
  ASSERT_FALSE(both.profile.empty());
  EXPECT_EQ(both.profile.front().stage, "forms");
  EXPECT_EQ(both.profile.front().method, "cmds+smacof");
  for (const RetrievalMethodResult& m : both.methods) {
    EXPECT_EQ(m.forms_computed, 6) << m.method;
    EXPECT_EQ(m.forms_cached, 0) << m.method;
  }
  for (const std::string& method : o.methods) {
    RetrievalExperimentOptions alone = o;
    alone.methods = {method};
    alone.out = dir + "/alone-" + method;
    const RetrievalExperimentResult a = retrieval_experiment(alone);
    EXPECT_EQ(a.methods[0].forms_computed, 6);
    for (const std::string& kind : retrieval_distances())
      EXPECT_EQ(read_text_file(alone.out + "/" + method + "/" + kind + ".csv"),
                read_text_file(o.out + "/" + method + "/" + kind + ".csv"))
          << method << " " << kind;
  }
}

// Two-stage mode beside an exact run: the candidates' pairs only, recall@K and the exact measures from the
// reference; K = N − 1 aligns every pair and gives the exact run's matrices and measures.
TEST(RetrievalExperiment, TwoStageReportsRecallAndTheExactMeasures) {
  const std::string dir = test::scratch_dir("retrieval-experiment-two-stage");
  RetrievalExperimentOptions exact = fast_options(dir);
  exact.figures = false;
  const RetrievalExperimentResult e = retrieval_experiment(exact);
  const RetrievalScores exact_scores = e.methods[0].by_distance.at("hausdorff").result.mean;

  RetrievalExperimentOptions o = exact;
  o.out = dir + "/two-stage";
  o.two_stage_k = 1;
  o.two_stage_reference = exact.out;
  const RetrievalExperimentResult r = retrieval_experiment(o);
  const RetrievalMethodResult& m = r.methods[0];
  EXPECT_LT(m.pairs_aligned, 15);  // each shape's nearest candidate: at most 6 distinct pairs
  EXPECT_LE(m.pairs_aligned, 6);
  EXPECT_GE(m.recall, 0);
  EXPECT_LE(m.recall, 1);
  ASSERT_EQ(m.exact.count("hausdorff"), 1u);
  EXPECT_EQ(m.exact.at("hausdorff").ap, exact_scores.ap);
  EXPECT_EQ(m.exact.at("hausdorff").nn, exact_scores.nn);
  const nlohmann::json j = nlohmann::json::parse(read_text_file(o.out + "/retrieval.json"));
  EXPECT_EQ(j["protocol"]["two_stage_k"], 1);
  EXPECT_EQ(j["methods"][0]["two_stage"]["pairs_aligned"], m.pairs_aligned);
  EXPECT_NE(read_text_file(o.out + "/report.md").find("## Two-stage retrieval"), std::string::npos);
  // The exact run's protocol has no two-stage key (runs before the mode existed compare with it).
  EXPECT_FALSE(nlohmann::json::parse(read_text_file(exact.out + "/retrieval.json"))["protocol"].contains(
      "two_stage_k"));

  o.out = dir + "/all-candidates";
  o.two_stage_k = 5;
  const RetrievalExperimentResult all = retrieval_experiment(o);
  EXPECT_EQ(all.methods[0].pairs_aligned, 15);
  EXPECT_EQ(all.methods[0].recall, 1.0);
  EXPECT_EQ(read_text_file(o.out + "/cmds/hausdorff.csv"), read_text_file(exact.out + "/cmds/hausdorff.csv"));
  EXPECT_EQ(all.methods[0].by_distance.at("hausdorff").result.mean.ap, exact_scores.ap);
}

TEST(RetrievalExperiment, TwoStageRefusesAReferenceItWouldOverwriteOrCannotUse) {
  const std::string dir = test::scratch_dir("retrieval-experiment-two-stage-refusals");
  RetrievalExperimentOptions exact = fast_options(dir);
  exact.figures = false;
  retrieval_experiment(exact);
  RetrievalExperimentOptions o = exact;
  o.two_stage_reference = exact.out;
  o.out = dir + "/two-stage";
  // Without K.
  EXPECT_NE(test::error_of([&] { retrieval_experiment(o); }).find("applies to the two-stage mode only"),
            std::string::npos);
  o.two_stage_k = 2;
  // Into the reference's own folder: the rerun would remove the exact run's outputs.
  o.out = exact.out;
  EXPECT_NE(test::error_of([&] { retrieval_experiment(o); }).find("the exact run would be lost"), std::string::npos);
  EXPECT_TRUE(fs::exists(exact.out + "/cmds/hausdorff.csv"));
  // A method the reference did not run.
  o.out = dir + "/two-stage";
  o.methods = {"lbo"};
  EXPECT_NE(test::error_of([&] { retrieval_experiment(o); }).find("no lbo/hausdorff.csv"), std::string::npos);
  EXPECT_FALSE(fs::exists(o.out + "/lbo"));
}

// The run returns the data and writes no report; the writer makes report.md from the result alone.
TEST(RetrievalExperiment, RunWritesNoReportTheWriterUsesTheResult) {
  const std::string dir = test::scratch_dir("retrieval-experiment-run");
  const RetrievalExperimentOptions o = fast_options(dir);
  const RetrievalExperimentResult r = run_retrieval_experiment(o);
  EXPECT_FALSE(fs::exists(o.out + "/report.md"));
  write_retrieval_report(r, dir + "/elsewhere");
  EXPECT_NE(read_text_file(dir + "/elsewhere/report.md").find("classical MDS"), std::string::npos);
}

// --resample: each shape remeshed to about N vertices, its measures recorded (Hausdorff against the input
// recomputed here), classes and order kept, and a second run reading every remesh from the cache.
TEST(ResampledDataset, RemeshesKeepsClassesAndCachesByContent) {
  const std::string dir = test::scratch_dir("resampled-dataset");
  const std::string data = tiny_collection(dir);
  ResampleOptions ro;
  ro.vertices = 100;
  ro.tolerance = 0.05;
  const DiskCache cache(dir + "/cache");
  const ResampledDataset r = resample_dataset(data, ro, dir + "/resampled", cache);
  ASSERT_EQ(r.shapes.size(), 6u);
  EXPECT_EQ(r.computed, 6);
  const Dataset before = read_dataset(data), after = read_dataset(r.data);
  ASSERT_EQ(after.entries.size(), 6u);
  for (size_t k = 0; k < 6; ++k) {
    const ResampledShape& s = r.shapes[k];
    EXPECT_EQ(after.entries[k].name, before.entries[k].name);
    EXPECT_EQ(after.entries[k].class_name, before.entries[k].class_name);
    ASSERT_TRUE(s.remeshed) << s.note;
    const Mesh input = read_mesh(before.entries[k].path), remeshed = read_mesh(after.entries[k].path);
    EXPECT_EQ(s.input_vertices, input.num_vertices());
    EXPECT_EQ(s.vertices, remeshed.num_vertices());
    EXPECT_NEAR(static_cast<double>(s.vertices), 100.0, 5.0) << s.name;
    const double diagonal = (input.V.colwise().maxCoeff() - input.V.colwise().minCoeff()).norm();
    EXPECT_NEAR(s.hausdorff, hausdorff_distance(input, remeshed) / diagonal, 1e-6) << s.name;
    EXPECT_GT(s.hausdorff, 0);
    EXPECT_LT(s.hausdorff, 0.1);
    EXPECT_NEAR(s.min_angle, angle_stats(remeshed).min_angle, 1e-9);
    EXPECT_GT(s.min_angle, 0);
  }
  const ResampledDataset again = resample_dataset(data, ro, dir + "/resampled2", cache);
  EXPECT_EQ(again.computed, 0);
  EXPECT_EQ(again.cached, 6);
  EXPECT_EQ(read_file(dir + "/resampled2/sphere1.off"), read_file(dir + "/resampled/sphere1.off"));
  const std::string md = resampling_markdown(r);
  EXPECT_NE(md.find("| torus2 |"), std::string::npos);
  EXPECT_TRUE(fs::exists(dir + "/resampled/resample.csv"));
}

// The experiment with resample: the report shows the remeshes, the matrices are over the remeshed shapes.
TEST(ResampledDataset, TheExperimentRunsOnTheRemeshedShapes) {
  const std::string dir = test::scratch_dir("retrieval-resampled");
  RetrievalExperimentOptions o = fast_options(dir);
  o.resample.vertices = 120;
  o.figures = false;
  const RetrievalExperimentResult r = retrieval_experiment(o);
  ASSERT_TRUE(r.resampled);
  EXPECT_EQ(r.resampling.shapes.size(), 6u);
  EXPECT_EQ(r.data, o.out + "/resampled/manifest.csv");
  EXPECT_EQ(r.methods[0].names.size(), 6u);
  const std::string report = read_text_file(o.out + "/report.md");
  EXPECT_NE(report.find("## Resampling"), std::string::npos);
  EXPECT_NE(report.find("remeshed to about 120 vertices"), std::string::npos);
}

}  // namespace retrieval_experiment_test
}  // namespace cshapes

namespace cshapes {
namespace retrieval_experiment_test {

// The command line: --resample's values, and distmat reading a .cla collection with --resample.
TEST(RetrievalCli, ResampleOptionAndClaCollectionOnDistmat) {
  const std::string dir = test::scratch_dir("retrieval-cli");
  const std::string data = tiny_collection(dir);
  test::CliResult bad = test::run_cli("experiment retrieval --data '" + data + "' --out '" + dir +
                                      "/out' --resample 2");
  EXPECT_EQ(bad.exit_code, 2);
  EXPECT_NE(bad.err.find("--resample"), std::string::npos) << bad.err;
  EXPECT_FALSE(fs::exists(dir + "/out"));
  test::write_text(data + "/c.cla",
                   "PSB 1\n2 6\n\nsphere 0 3\nsphere0\nsphere1\nsphere2\n\ntorus 0 3\ntorus0\ntorus1\ntorus2\n");
  test::CliResult r = test::run_cli("-q distmat '" + data + "/c.cla' -o '" + dir +
                                    "/d.csv' --method cmds --geodesics graph --resample 100 --json");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const nlohmann::json j = nlohmann::json::parse(r.out);
  EXPECT_EQ(j["shapes"], 6);
  EXPECT_EQ(j["resample"]["vertices"], 100);
  EXPECT_EQ(j["resample"]["remeshes_computed"], 6);
  const Dataset resampled = read_dataset(dir + "/.cshapes-cache/resampled-100/manifest.csv");
  ASSERT_EQ(resampled.entries.size(), 6u);
  EXPECT_NEAR(static_cast<double>(read_mesh(resampled.entries[4].path).num_vertices()), 100.0, 2.0);
  EXPECT_EQ(read_distance_csv(dir + "/d.csv").names,
            (std::vector<std::string>{"sphere0", "sphere1", "sphere2", "torus0", "torus1", "torus2"}));
}

}  // namespace retrieval_experiment_test
}  // namespace cshapes

namespace cshapes {
namespace retrieval_experiment_test {

// `experiment paper` and `experiment noise` with resample: they run on the remeshed shapes and their reports
// show the remeshes (the data named is the one given).
TEST(ResampledDataset, PaperAndNoiseExperimentsRunOnTheRemeshes) {
  const std::string dir = test::scratch_dir("resampled-experiments");
  const std::string data = test::generated_dataset(dir + "/gen", 2, 3, 400);
  PaperExperimentOptions p;
  p.data = data;
  p.out = dir + "/paper";
  p.methods = {"coulomb"};
  p.poses_per_class = 3;
  p.noisy_per_class = 0;
  p.correspondence_samples = 0;
  p.table1 = false;
  p.figures = false;
  p.resample.vertices = 250;
  paper_experiment(p);
  const std::string paper = read_text_file(p.out + "/report.md");
  EXPECT_NE(paper.find("## Resampling"), std::string::npos);
  EXPECT_NE(paper.find(data), std::string::npos);
  EXPECT_NE(read_text_file(p.out + "/labels.csv").find(",250,"), std::string::npos);  // vertices of the shapes used
  NoiseExperimentOptions n;
  n.data = data;
  n.out = dir + "/noise";
  n.methods = {"coulomb"};
  n.levels = {0, 1};
  n.poses_per_class = 2;
  n.relax_steps = 6;
  n.figure = false;
  n.resample.vertices = 250;
  const NoiseExperimentResult r = noise_experiment(n);
  ASSERT_TRUE(r.resampled);
  for (const NoisePose& pose : r.pose_list) EXPECT_NEAR(static_cast<double>(pose.vertices), 250.0, 3.0);
  const std::string noise = read_text_file(n.out + "/report.md");
  EXPECT_NE(noise.find("## Resampling"), std::string::npos);
  EXPECT_NE(noise.find(data), std::string::npos);
}

}  // namespace retrieval_experiment_test
}  // namespace cshapes
