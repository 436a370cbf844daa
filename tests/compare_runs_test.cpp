// `cshapes compare` (experiments/compare_runs.h) on tiny generated collections: two runs with different
// methods on the same data merge; the same data in another folder is the same data (by content); different
// data, a method with two results, an old run without checksums, another experiment's outputs and a missing
// folder are refused, writing nothing. And the inputs' digest (data/dataset_checksums.h) it rests on.
#include "cshapes/experiments/compare_runs.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <nlohmann/json.hpp>

#include "cshapes/data/dataset.h"
#include "cshapes/data/dataset_checksums.h"
#include "cshapes/data/synthetic.h"
#include "cshapes/experiments/retrieval_experiment.h"
#include "cshapes/mesh/io.h"
#include "cshapes/pipeline/outside_methods.h"
#include "cshapes/support/atomic_file.h"
#include "cshapes/support/sha256.h"
#include "tests/test_support.h"

namespace cshapes {
namespace compare_runs_test {

namespace fs = std::filesystem;
using nlohmann::json;

// Three spheres and three tori of different sizes (two classes of three, about 160 vertices each); `bigger`
// makes the second sphere a little larger: another collection under the same names.
std::string tiny_collection(const std::string& folder, bool bigger = false) {
  for (int k = 0; k < 3; ++k) {
    const double sphere_radius = 1.0 + 0.1 * k + (bigger && k == 1 ? 0.05 : 0.0);
    write_mesh(folder + "/sphere" + std::to_string(k) + ".off", icosphere(2, sphere_radius));
    write_mesh(folder + "/torus" + std::to_string(k) + ".off", torus(16, 10, 1.0 + 0.1 * k, 0.3 + 0.03 * k));
  }
  return folder;
}

std::string run(const std::string& data, const std::string& out, const std::vector<std::string>& methods) {
  RetrievalExperimentOptions o;
  o.data = data;
  o.out = out;
  o.methods = methods;
  o.canon.geodesics.method = GeodesicMethod::Graph;
  o.figures = false;
  retrieval_experiment(o);
  return out;
}

json read_json(const std::string& path) {
  return json::parse(read_text_file(path));
}

// The runs every test reads, computed once: cmds and lbo on one collection, lbo and cmds on a copy of it in
// another folder, cmds on a collection with one sphere changed.
class CompareRuns : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    dir = new std::string(test::scratch_dir("compare-runs"));
    const std::string data = tiny_collection(*dir + "/data");
    const std::string copy = tiny_collection(*dir + "/copy");
    const std::string other = tiny_collection(*dir + "/other", /*bigger=*/true);
    run(data, *dir + "/cmds", {"cmds"});
    run(data, *dir + "/lbo", {"lbo"});
    run(copy, *dir + "/both-on-copy", {"lbo", "cmds"});
    run(other, *dir + "/cmds-other", {"cmds"});
    // A method from outside by the command door: the input as its own form.
    OutsideDoor door;
    door.kind = OutsideDoor::Kind::Command;
    door.text = "cp {mesh} {form.off}";
    const OutsideMethod ident("ident", door);
    run(data, *dir + "/ident", {"ident"});
  }
  static void TearDownTestSuite() { delete dir; }

  static CompareRunsOptions options(std::vector<std::string> runs, const std::string& out) {
    CompareRunsOptions o;
    for (std::string& r : runs) r = *dir + "/" + r;
    o.runs = runs;
    o.out = *dir + "/" + out;
    o.figures = false;
    return o;
  }
  // The refusal's message; the output folder must not exist afterwards (nothing written).
  static std::string refusal(const CompareRunsOptions& o) {
    try {
      compare_runs(o);
    } catch (const Error& e) {
      EXPECT_FALSE(fs::exists(o.out)) << "a refused comparison wrote " << o.out;
      return e.what();
    }
    ADD_FAILURE() << "not refused";
    return "";
  }

  static std::string* dir;
};
std::string* CompareRuns::dir = nullptr;

TEST_F(CompareRuns, TwoRunsWithDifferentMethodsMerge) {
  const CompareRunsOptions o = options({"cmds", "lbo"}, "merged");
  const CompareRunsResult r = compare_runs(o);
  EXPECT_EQ(r.experiment, "retrieval");
  EXPECT_EQ(r.shapes, 6);
  ASSERT_EQ(r.methods.size(), 2u);
  EXPECT_EQ(r.methods[0].method, "cmds");
  EXPECT_EQ(r.methods[0].run, 0u);
  EXPECT_EQ(r.methods[1].method, "lbo");
  EXPECT_EQ(r.methods[1].run, 1u);
  EXPECT_EQ(r.distances, retrieval_distances());
  // Every number is the run's own, as its retrieval.json holds it.
  const json merged = read_json(o.out + "/compare.json");
  for (size_t k = 0; k < 2; ++k) {
    const json own = read_json(o.runs[k] + "/retrieval.json");
    EXPECT_EQ(own["inputs"]["digest"], merged["inputs"]["digest"]);
    for (const std::string& kind : retrieval_distances()) {
      const json& mine = merged["methods"][k]["distances"][kind];
      const json& theirs = own["methods"][0]["distances"][kind];
      EXPECT_EQ(mine["map"], theirs["map"]) << kind;
      EXPECT_EQ(mine["pr"], theirs["pr"]) << kind;
    }
    EXPECT_EQ(merged["methods"][k]["run"], o.runs[k]);
  }
  // One table, each row naming its run folder.
  const std::string report = read_text_file(o.out + "/report.md");
  EXPECT_NE(report.find("| classical MDS | Hausdorff (the paper's) | 6 |"), std::string::npos) << report;
  EXPECT_NE(report.find("| LBO eigenmap | RMSE | 6 |"), std::string::npos) << report;
  EXPECT_NE(report.find("`" + o.runs[1] + "` |"), std::string::npos) << report;
  EXPECT_NE(report.find(r.inputs_digest), std::string::npos);
  // A rerun replaces the set (OutputRun), and the folder is its own.
  EXPECT_NO_THROW(compare_runs(o));
}

TEST_F(CompareRuns, SameDataInAnotherFolderIsTheSameDataAndOneMethodIsOneRow) {
  // both-on-copy read a copy of the collection elsewhere: the same content, so the same data; its cmds has
  // the same results as the cmds run's, so it is one row, from the first run, the other named beside it.
  const CompareRunsOptions o = options({"cmds", "both-on-copy"}, "with-copy");
  const CompareRunsResult r = compare_runs(o);
  ASSERT_EQ(r.methods.size(), 2u);
  EXPECT_EQ(r.methods[0].method, "cmds");
  EXPECT_EQ(r.methods[0].run, 0u);
  EXPECT_EQ(r.methods[0].also_in, std::vector<size_t>{1});
  EXPECT_EQ(r.methods[1].method, "lbo");
  EXPECT_EQ(r.methods[1].run, 1u);
  EXPECT_NE(read_text_file(o.out + "/report.md").find("(also `" + o.runs[1] + "`)"), std::string::npos);
}

TEST_F(CompareRuns, AMethodFromOutsideKeepsItsDoor) {
  const CompareRunsOptions o = options({"cmds", "ident"}, "with-outside");
  const CompareRunsResult r = compare_runs(o);
  ASSERT_EQ(r.methods.size(), 2u);
  EXPECT_EQ(r.methods[0].door, "");
  EXPECT_EQ(r.methods[1].method, "ident");
  EXPECT_EQ(r.methods[1].door, "command");
  EXPECT_EQ(r.methods[1].door_text, "cp {mesh} {form.off}");
  const std::string report = read_text_file(o.out + "/report.md");
  EXPECT_NE(report.find("## Methods from outside"), std::string::npos) << report;
  EXPECT_NE(report.find("by the command door, `cp {mesh} {form.off}`"), std::string::npos) << report;
  EXPECT_EQ(read_json(o.out + "/compare.json")["methods"][1]["door"], "command");
}

TEST_F(CompareRuns, DifferentDataIsRefusedNamingTheShape) {
  const std::string message = refusal(options({"cmds", "cmds-other"}, "refused-data"));
  EXPECT_NE(message.find("not run on the same data"), std::string::npos) << message;
  EXPECT_NE(message.find("sphere1"), std::string::npos) << message;
  EXPECT_NE(message.find("cmds-other"), std::string::npos) << message;
}

TEST_F(CompareRuns, OneMethodWithTwoResultsIsRefused) {
  // A copy of the lbo run whose Hausdorff mAP was changed: the same data, the same name, another result.
  const std::string changed = *dir + "/lbo-changed";
  fs::copy(*dir + "/lbo", changed, fs::copy_options::recursive | fs::copy_options::overwrite_existing);
  json j = read_json(changed + "/retrieval.json");
  j["methods"][0]["distances"]["hausdorff"]["map"] = 0.123;
  test::write_text(changed + "/retrieval.json", j.dump(2));
  const std::string message = refusal(options({"lbo", "lbo-changed"}, "refused-method"));
  EXPECT_NE(message.find("method lbo"), std::string::npos) << message;
  EXPECT_NE(message.find("different results"), std::string::npos) << message;
  EXPECT_NE(message.find("mAP"), std::string::npos) << message;
}

TEST_F(CompareRuns, RunsWithoutChecksumsOtherExperimentsAndMissingFoldersAreRefused) {
  // A run written before runs recorded their inputs: rerun it.
  const std::string old = *dir + "/cmds-old";
  fs::copy(*dir + "/cmds", old, fs::copy_options::recursive | fs::copy_options::overwrite_existing);
  json j = read_json(old + "/retrieval.json");
  j.erase("inputs");
  test::write_text(old + "/retrieval.json", j.dump(2));
  std::string message = refusal(options({"cmds-old", "lbo"}, "refused-old"));
  EXPECT_NE(message.find("no checksums of its inputs"), std::string::npos) << message;
  EXPECT_NE(message.find("rerun"), std::string::npos) << message;
  // Another experiment's outputs: named, with what is supported.
  fs::create_directories(*dir + "/noise");
  test::write_text(*dir + "/noise/.cshapes-outputs",
                   "cshapes output folder 1\ncommand experiment noise\nstate complete\n");
  message = refusal(options({"cmds", "noise"}, "refused-noise"));
  EXPECT_NE(message.find("experiment noise"), std::string::npos) << message;
  EXPECT_NE(message.find("experiment retrieval"), std::string::npos) << message;
  // A missing folder, a folder given twice, one run, the output inside a run.
  message = refusal(options({"cmds", "no-such-run"}, "refused-missing"));
  EXPECT_NE(message.find("no-such-run: no such folder"), std::string::npos) << message;
  message = refusal(options({"cmds", "cmds"}, "refused-twice"));
  EXPECT_NE(message.find("given twice"), std::string::npos) << message;
  message = refusal(options({"cmds"}, "refused-one"));
  EXPECT_NE(message.find("two or more"), std::string::npos) << message;
  message = refusal(options({"cmds", "lbo"}, "cmds/compare"));
  EXPECT_NE(message.find("may not be a run's folder"), std::string::npos) << message;
}

TEST(DatasetChecksums, ByContentNotByPlaceOrOrder) {
  const std::string dir = test::scratch_dir("dataset-checksums");
  const DatasetChecksums a = dataset_checksums(read_dataset(tiny_collection(dir + "/a")));
  const DatasetChecksums b = dataset_checksums(read_dataset(tiny_collection(dir + "/b")));
  const DatasetChecksums c = dataset_checksums(read_dataset(tiny_collection(dir + "/c", /*bigger=*/true)));
  ASSERT_EQ(a.shapes.size(), 6u);
  EXPECT_EQ(a.shapes[0].sha256, file_content_hash(dir + "/a/sphere0.off"));
  EXPECT_EQ(a.digest, b.digest);
  EXPECT_NE(a.digest, c.digest);
  std::vector<ShapeChecksum> reversed(a.shapes.rbegin(), a.shapes.rend());
  EXPECT_EQ(dataset_digest(reversed), a.digest);  // the listing's order is no part of the data
  std::vector<ShapeChecksum> relabelled = a.shapes;
  relabelled[0].class_name = "torus";
  EXPECT_NE(dataset_digest(relabelled), a.digest);  // the classes are
}

}  // namespace compare_runs_test
}  // namespace cshapes
