// `cshapes experiment noise` (experiments/noise_experiment.h) on a small generated dataset: the outputs'
// structure, χ recorded and checked for every glued mesh, level 0 equal to the clean forms (form distance 0),
// mAP in [0, 1], and a rerun that computes nothing; the driver and its writers without the CLI. Also the
// known answers of glue_seed, and `experiment paper --noisy-per-class all` with its retrieval under
// Hausdorff, Chamfer and RMSE.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <limits>
#include <map>
#include <nlohmann/json.hpp>
#include <set>
#include <sstream>

#include "cshapes/support/atomic_file.h"
#include "cshapes/support/error.h"
#include "cshapes/mesh/io.h"
#include "cshapes/data/synthetic.h"
#include "cshapes/eval/distance_csv.h"
#include "cshapes/experiments/noise_experiment.h"
#include "cshapes/pipeline/canonical_forms.h"
#include "cshapes/pipeline/shape_failures.h"
#include "test_support.h"

namespace cshapes {
namespace noise_experiment_test {

namespace fs = std::filesystem;

// 2 classes × 3 clean poses of 400 vertices (no noisy shapes): a few seconds per run.
std::string small_dataset(const std::string& tag) {
  const std::string dir = test::scratch_dir(tag);
  test::CliResult r = test::run_cli("-q generate dataset --out '" + dir +
                                    "/data' --classes 2 --poses 3 --noisy 0 --vertices 400");
  EXPECT_EQ(r.exit_code, 0) << r.err;
  return dir;
}

nlohmann::json run_json(const std::string& arguments) {
  test::CliResult r = test::run_cli(arguments + " --json");
  EXPECT_EQ(r.exit_code, 0) << r.err;
  return nlohmann::json::parse(r.out.empty() ? "{}" : r.out);
}

std::vector<std::vector<std::string>> read_csv_rows(const std::string& path) {
  std::ifstream in(path);
  std::vector<std::vector<std::string>> rows;
  std::string line;
  while (std::getline(in, line)) {
    std::vector<std::string> cells;
    std::stringstream ss(line);
    std::string cell;
    while (std::getline(ss, cell, ',')) cells.push_back(cell);
    rows.push_back(cells);
  }
  return rows;
}

TEST(NoiseExperiment, GlueSeedsAreDeterministicAndDistinct) {
  EXPECT_EQ(glue_seed(1, "cat0", 2), glue_seed(1, "cat0", 2));
  std::set<std::uint64_t> seeds;
  for (std::uint64_t base : {1, 2})
    for (const char* shape : {"cat0", "cat1", "dog0"})
      for (int level : {1, 2, 4, 8}) seeds.insert(glue_seed(base, shape, level));
  EXPECT_EQ(seeds.size(), 24u);
}

// The driver without the CLI: run_noise_experiment returns the data and writes no report; the writers make
// noise.csv, noise.json and report.md from the result alone.
TEST(NoiseExperiment, RunReturnsTheDataAndTheWritersUseItAlone) {
  const std::string dir = test::scratch_dir("noise-library");
  NoiseExperimentOptions o;
  o.data = test::generated_dataset(dir, 2, 3, 400);
  o.out = dir + "/out";
  o.methods = {"coulomb"};
  o.levels = {1, 0};  // sorted by the run
  o.relax_steps = 6;  // every pose of this small set glued in portable and native builds alike
  const NoiseExperimentResult r = run_noise_experiment(o);
  EXPECT_EQ(r.options.levels, (std::vector<int>{0, 1}));
  ASSERT_EQ(r.pose_list.size(), 6u);
  EXPECT_EQ(r.poses, 6);
  EXPECT_EQ(r.classes, 2);
  ASSERT_EQ(r.glues.size(), 6u);  // every pose at level 1
  for (const NoiseGlue& g : r.glues) EXPECT_EQ(g.chi_after, g.chi_before - 2) << g.shape << ": " << g.error;
  ASSERT_EQ(r.rows.size(), 6u);  // 1 method × 2 levels × 3 distances
  for (const NoiseRow& row : r.rows) {
    EXPECT_EQ(row.queries, 6);
    EXPECT_EQ(row.form_poses, 6);
    if (row.level == 0) {
      EXPECT_LT(row.form_rms_median, 1e-12) << "level 0 is the clean form itself";
      EXPECT_DOUBLE_EQ(row.map_clean_same_poses, row.map);
    }
  }
  EXPECT_TRUE(r.per_query.contains("coulomb"));
  EXPECT_FALSE(fs::exists(o.out + "/noise.csv")) << "the run writes data files only through the writers";
  EXPECT_FALSE(fs::exists(o.out + "/report.md"));

  const std::string elsewhere = dir + "/written";
  write_noise_outputs(r, elsewhere);
  write_noise_report(r, elsewhere);
  EXPECT_EQ(read_csv_rows(elsewhere + "/noise.csv").size(), 7u);
  const nlohmann::json j = nlohmann::json::parse(read_file(elsewhere + "/noise.json"));
  EXPECT_EQ(j["poses"].size(), 6u);
  EXPECT_EQ(j["levels"], nlohmann::json::array({0, 1}));
  const std::string report = read_file(elsewhere + "/report.md");
  EXPECT_NE(report.find("| Coulomb | 1 | 6 | 6 |"), std::string::npos) << report;

  // A second run computes nothing: glued meshes, forms and pairs come from the cache, to the same rows.
  const NoiseExperimentResult again = run_noise_experiment(o);
  EXPECT_EQ(again.glued_computed, 0);
  EXPECT_EQ(again.canonical_forms_computed, 0);
  EXPECT_EQ(again.pairs_computed, 0);
  ASSERT_EQ(again.rows.size(), r.rows.size());
  for (size_t k = 0; k < r.rows.size(); ++k) EXPECT_EQ(again.rows[k].map, r.rows[k].map);
}

// The report writer on a hand-made result: what is measured is in its table, what is not is "—", a glue
// that failed and a shape left out are named, and a missing figure says why.
TEST(NoiseExperiment, ReportWriterSaysWhatTheResultHolds) {
  NoiseExperimentResult r;
  r.options.data = "DATA";
  r.options.methods = {"coulomb", "cmds"};
  r.options.levels = {0, 4};
  r.pose_list = {{"cat0", "cat", "cat0.off", 100, 2}, {"cat1", "cat", "cat1.off", 100, 2}};
  r.poses = 2;
  r.classes = 1;
  NoiseGlue failed;
  failed.shape = "cat1";
  failed.level = 4;
  failed.ok = false;
  failed.error = "glue failed: too few admissible spots";
  r.glues = {failed};
  r.glue_failures = 1;
  for (const std::string m : {"coulomb", "cmds"})
    for (int level : {0, 4})
      for (const char* kind : {"hausdorff", "chamfer", "rmse"}) {
        NoiseRow row;
        row.method = m;
        row.level = level;
        row.distance = kind;
        row.queries = level == 0 ? 2 : 0;
        row.map = level == 0 ? 0.75 : std::numeric_limits<double>::quiet_NaN();
        row.nn = level == 0 ? 0.5 : std::numeric_limits<double>::quiet_NaN();
        row.form_rms_median = level == 0 ? 0 : std::numeric_limits<double>::quiet_NaN();
        row.form_rms_mean = row.form_rms_median;
        r.rows.push_back(row);
      }
  r.failures.push_back(read_failure("dog0", "dog0.off", Error("dog0.off: not a mesh")));
  r.figure_note = "no Python with matplotlib.";
  const std::string dir = test::scratch_dir("noise-report");
  write_noise_report(r, dir);
  const std::string report = read_file(dir + "/report.md");
  EXPECT_NE(report.find("| Coulomb | 0 | 0 | 2 | 0.750 |"), std::string::npos) << report;
  EXPECT_NE(report.find("| classical MDS | 4 | 0 | 0 | — |"), std::string::npos) << report;
  EXPECT_NE(report.find("| cat1 | 4 |"), std::string::npos) << "the failed glue is listed";
  EXPECT_NE(report.find("too few admissible spots"), std::string::npos);
  EXPECT_NE(report.find("dog0"), std::string::npos) << "the shape left out is named";
  EXPECT_NE(report.find("No figure: no Python with matplotlib."), std::string::npos);
}

TEST(NoiseExperimentCli, StructureChiLevelZeroAndResume) {
  const std::string dir = small_dataset("noise-experiment");
  const std::string out = dir + "/out";
  const std::string command =
      "-q experiment noise --data '" + dir + "/data' --out '" + out + "' --levels 0,1,2 --geodesics graph" +
      // Up to 6 relaxations: with 3, one of these 400-vertex poses offers only one admissible pair at level 2
      // in a portable build (which almost-touching pairs qualify moves with last-bit differences).
      " --relax-steps 6";
  const nlohmann::json first = run_json(command);
  const int methods = static_cast<int>(canonical_form_methods().size());  // every registered one (default)
  EXPECT_EQ(first["poses"], 6);
  EXPECT_EQ(first["classes"], 2);
  EXPECT_EQ(first["glued"], 12);  // 6 poses × levels 1, 2
  EXPECT_EQ(first["chi_mismatches"], 0);
  EXPECT_EQ(first["glue_failures"], 0);
  EXPECT_EQ(first["glued_computed"], 12);
  EXPECT_EQ(first["canonical_forms_computed"], 18 * methods);  // 18 shapes × the methods
  EXPECT_EQ(first["canonical_forms_cached"], 0);
  // Per method: level 0 the 15 clean pairs, levels 1 and 2 each 6 queries × 5 clean poses.
  EXPECT_EQ(first["pairs_computed"], methods * (15 + 2 * 30));

  // noise.csv: the methods × 3 levels × 3 distances.
  const auto rows = read_csv_rows(out + "/noise.csv");
  ASSERT_EQ(rows.size(), static_cast<size_t>(methods * 9 + 1));
  EXPECT_EQ(rows[0], (std::vector<std::string>{"method", "level", "distance", "queries", "map", "nn",
                                               "form_rms_median", "form_rms_mean", "form_poses",
                                               "map_clean_same_poses"}));
  std::set<std::string> seen;
  std::map<std::string, double> clean_map;
  for (size_t k = 1; k < rows.size(); ++k) {
    const auto& r = rows[k];
    ASSERT_EQ(r.size(), 10u);
    seen.insert(r[0] + "/" + r[1] + "/" + r[2]);
    EXPECT_EQ(r[3], "6");  // every pose is a query with two relevant poses
    const double map = std::stod(r[4]), nn = std::stod(r[5]);
    EXPECT_GE(map, 0.0);
    EXPECT_LE(map, 1.0);
    EXPECT_GE(nn, 0.0);
    EXPECT_LE(nn, 1.0);
    EXPECT_GE(map, (1.0 / 4 + 2.0 / 5) / 2 - 1e-12);  // two relevant of five, at worst ranked 4th and 5th
    const double median = std::stod(r[6]), mean = std::stod(r[7]);
    EXPECT_EQ(r[8], "6");
    // Every pose is measured at every level here, so the clean baseline is level 0's mAP.
    clean_map[r[0] + "/" + r[1] + "/" + r[2]] = std::stod(r[9]);
    if (r[1] == "0") {
      EXPECT_EQ(r[9], r[4]);
      EXPECT_LT(median, 1e-9) << "level 0 is the clean form itself";
      EXPECT_LT(mean, 1e-9);
    } else {
      EXPECT_GT(mean, 0.0) << "a glued form moved not at all: " << r[0] << " level " << r[1];
      EXPECT_LT(mean, 1.0);
    }
  }
  EXPECT_EQ(seen.size(), static_cast<size_t>(methods * 9));
  for (const auto& [key, value] : clean_map) {
    const std::string level0 = key.substr(0, key.find('/')) + "/0" + key.substr(key.rfind('/'));
    EXPECT_NEAR(value, clean_map.at(level0), 1e-12) << key;
  }

  // noise.json: χ before and after every glue, as the noise module promises (χ − 2 per glue).
  const nlohmann::json j = nlohmann::json::parse(read_file(out + "/noise.json"));
  ASSERT_EQ(j["poses"].size(), 6u);
  ASSERT_EQ(j["glues"].size(), 12u);
  std::set<std::uint64_t> seeds;
  for (const auto& g : j["glues"]) {
    EXPECT_TRUE(g["ok"].get<bool>()) << g.dump();
    EXPECT_EQ(g["chi_expected"].get<long>(), g["chi_before"].get<long>() - 2 * g["level"].get<long>());
    EXPECT_EQ(g["chi_after"], g["chi_expected"]);
    seeds.insert(g["seed"].get<std::uint64_t>());
    const std::string glued = out + "/shapes/" + g["shape"].get<std::string>() + "_glue" +
                              std::to_string(g["level"].get<int>()) + ".off";
    ASSERT_TRUE(fs::exists(glued)) << glued;
    EXPECT_EQ(mesh_info(read_mesh(glued)).euler_characteristic, g["chi_after"].get<long>());
  }
  EXPECT_EQ(seeds.size(), 12u);  // a seed per pose and level
  for (const char* kind : {"hausdorff", "chamfer", "rmse"})
    EXPECT_EQ(j["queries"]["coulomb"]["1"][kind].size(), 6u);
  const std::string report = read_file(out + "/report.md");
  EXPECT_NE(report.find("χ"), std::string::npos);
  EXPECT_NE(report.find("| Coulomb | 2 | 6 | 6 |"), std::string::npos) << report;
  if (first["figure"].get<bool>())
    EXPECT_TRUE(fs::exists(out + "/noise.png"));
  else
    EXPECT_NE(report.find("No figure"), std::string::npos);

  // A rerun computes nothing and writes the same table.
  const std::string csv = read_file(out + "/noise.csv");
  const nlohmann::json again = run_json(command + " --no-draw");
  EXPECT_EQ(again["glued_computed"], 0);
  EXPECT_EQ(again["glued_cached"], 12);
  EXPECT_EQ(again["canonical_forms_computed"], 0);
  EXPECT_EQ(again["canonical_forms_cached"], 18 * methods);
  EXPECT_EQ(again["pairs_computed"], 0);
  EXPECT_EQ(again["pairs_cached"], first["pairs_computed"]);
  EXPECT_EQ(read_file(out + "/noise.csv"), csv);
}

TEST(NoiseExperimentCli, ALevelNoPoseOffersIsReportedNotInvented) {
  // 60 glues on 400-vertex shapes: no pose offers that many admissible spots.
  const std::string dir = small_dataset("noise-too-many");
  const std::string out = dir + "/out";
  const nlohmann::json j = run_json("-q experiment noise --data '" + dir + "/data' --out '" + out +
                                    "' --methods coulomb --levels 0,60 --relax-steps 0");
  EXPECT_EQ(j["glue_failures"], 6);
  EXPECT_EQ(j["canonical_forms_computed"], 6);  // the clean poses only
  const auto rows = read_csv_rows(out + "/noise.csv");
  ASSERT_EQ(rows.size(), 7u);
  for (size_t k = 1; k < rows.size(); ++k) {
    if (rows[k][1] != "60") continue;
    EXPECT_EQ(rows[k][3], "0");  // no query
    EXPECT_EQ(rows[k][4], "nan");
    EXPECT_EQ(rows[k][8], "0");  // no pose measured
  }
  const nlohmann::json noise = nlohmann::json::parse(read_file(out + "/noise.json"));
  for (const auto& g : noise["glues"]) {
    EXPECT_FALSE(g["ok"].get<bool>());
    EXPECT_NE(g["error"].get<std::string>().find("glue failed"), std::string::npos) << g.dump();
  }
  const std::string report = read_file(out + "/report.md");
  EXPECT_NE(report.find("Not every pose could be glued"), std::string::npos) << report;
  EXPECT_NE(report.find("| Coulomb | 60 | 0 | 0 | — |"), std::string::npos) << report;
  if (j["figure"].get<bool>()) {
    EXPECT_TRUE(fs::exists(out + "/noise.png"));
  }
}

TEST(NoiseExperimentCli, APoseEveryMethodFailsOnIsLeftOutWithItsGluedVersions) {
  // A third pose of the first class that cannot be used (scaled to 1e150, one vertex at 1e300: its forms lie
  // beyond the sizes ICP's squared distances hold), added to the manifest.
  const std::string dir = small_dataset("noise-unusable");
  Mesh broken = icosphere(2);
  broken.V *= 1e150;
  broken.V.row(0).setConstant(1e300);
  write_mesh(dir + "/data/broken9.off", broken);
  const auto manifest = read_csv_rows(dir + "/data/manifest.csv");
  std::string line;
  for (size_t k = 0; k < manifest[0].size(); ++k)
    line += (k ? "," : "") + (manifest[0][k] == "file"    ? std::string("broken9.off")
                              : manifest[0][k] == "pose"  ? std::string("9")
                              : manifest[0][k] == "noisy" ? std::string("0")
                                                          : manifest[1][k]);
  std::ofstream(dir + "/data/manifest.csv", std::ios::app) << line << "\n";
  const std::string command = "experiment noise --data '" + dir +
                              "/data' --methods coulomb,cmds --levels 0,1 --coulomb-max-iterations 60 --json";
  test::CliResult r = test::run_cli(command + " --out '" + dir + "/out'");
  EXPECT_EQ(r.exit_code, 3) << r.err;
  EXPECT_NE(r.err.find("broken9 left out"), std::string::npos) << r.err;
  const nlohmann::json j = nlohmann::json::parse(r.out.empty() ? "{}" : r.out);
  EXPECT_EQ(j["poses"], 6);
  int left_out = 0;
  for (const auto& f : j["failures"]) left_out += f["left_out"].get<bool>() && f["name"] == "broken9";
  EXPECT_EQ(left_out, 1) << j["failures"].dump(2);
  const nlohmann::json noise = nlohmann::json::parse(read_file(dir + "/out/noise.json"));
  EXPECT_TRUE(noise.contains("failures"));
  for (const auto& [level, by_pose] : noise["form_rms"]["coulomb"].items())
    EXPECT_FALSE(by_pose.contains("broken9")) << level;
  EXPECT_NE(read_file(dir + "/out/report.md").find("| broken9 |"), std::string::npos);
  // --strict stops at it.
  r = test::run_cli("-q " + command + " --strict --out '" + dir + "/strict'");
  EXPECT_EQ(r.exit_code, 1) << r.err;
}

TEST(NoiseExperimentCli, RefusesBadLevels) {
  const std::string dir = test::scratch_dir("noise-levels");
  for (const char* levels : {"0,1,x", "1,1", "-2", ""}) {
    test::CliResult r = test::run_cli("-q experiment noise --data '" + dir + "' --out '" + dir +
                                      "/out' --levels '" + levels + "'");
    EXPECT_EQ(r.exit_code, 2) << levels << ": " << r.err;
    EXPECT_NE(r.err.find("--levels"), std::string::npos) << r.err;
  }
}

TEST(PaperExperimentCli, NoisyPerClassAllAndEveryDistance) {
  const std::string dir = small_dataset("paper-noisy-all");
  const std::string base = "-q experiment paper --data '" + dir +
                           "/data' --methods coulomb --no-table1 --no-figure-data --correspondence-samples 0 ";
  // 'all' with 2 poses per class in the retrieval set: every clean pose (the spare one too) gets a glued
  // version, so 2 classes × (2 clean + 3 noisy) shapes are compared.
  const std::string out = dir + "/all";
  run_json(base + "--poses-per-class 2 --noisy-per-class all --out '" + out + "'");
  const auto labels = read_csv_rows(out + "/labels.csv");
  ASSERT_EQ(labels.size(), 11u);  // header + 10 shapes
  int noisy = 0;
  for (size_t k = 1; k < labels.size(); ++k) noisy += labels[k][2] == "1";
  EXPECT_EQ(noisy, 6);
  // Every retrieval table under all three distances: metrics.json, the matrices, report.md.
  const nlohmann::json metrics = nlohmann::json::parse(read_file(out + "/metrics.json"));
  const auto& coulomb = metrics["methods"]["coulomb"];
  EXPECT_EQ(coulomb["map"], coulomb["by_distance"]["hausdorff"]["map"]);  // the top level stays Hausdorff
  for (const char* kind : {"hausdorff", "chamfer", "rmse"}) {
    const double map = coulomb["by_distance"][kind]["map"].get<double>();
    EXPECT_GE(map, 0.0);
    EXPECT_LE(map, 1.0);
    EXPECT_TRUE(coulomb["by_distance"][kind].contains("noisy_query_nn")) << kind;
  }
  const NamedDistances hausdorff = read_distance_csv(out + "/distances/coulomb.csv");
  const NamedDistances chamfer = read_distance_csv(out + "/distances/chamfer/coulomb.csv");
  const NamedDistances rmse = read_distance_csv(out + "/distances/rmse/coulomb.csv");
  ASSERT_EQ(chamfer.names, hausdorff.names);
  ASSERT_EQ(rmse.names, hausdorff.names);
  // Chamfer (means) and RMSE (a root mean square) of the nearest-point distances ≤ Hausdorff (their
  // maximum), pair by pair, and not all equal to it.
  const double tolerance = 1e-9 * hausdorff.D.maxCoeff();
  EXPECT_LE((chamfer.D - hausdorff.D).maxCoeff(), tolerance);
  EXPECT_LE((rmse.D - hausdorff.D).maxCoeff(), tolerance);
  EXPECT_LT(chamfer.D.sum(), hausdorff.D.sum());
  const std::string report = read_file(out + "/report.md");
  for (const char* row :
       {"| Coulomb | Hausdorff |", "| Coulomb | Chamfer |", "| Coulomb | RMSE |", "`--noisy-per-class all`"})
    EXPECT_NE(report.find(row), std::string::npos) << row << "\n" << report;

  // An integer keeps its meaning: one noisy shape per class.
  const std::string one = dir + "/one";
  run_json(base + "--poses-per-class 2 --noisy-per-class 1 --out '" + one + "'");
  EXPECT_EQ(read_csv_rows(one + "/labels.csv").size(), 7u);  // header + 2 × (2 clean + 1 noisy)

  test::CliResult bad = test::run_cli(base + "--noisy-per-class some --out '" + dir + "/bad'");
  EXPECT_EQ(bad.exit_code, 2);
  EXPECT_NE(bad.err.find("--noisy-per-class"), std::string::npos) << bad.err;
}

}  // namespace noise_experiment_test
}  // namespace cshapes
