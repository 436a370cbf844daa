// Issue 36 for the experiments beside `distmat` and `experiment retrieval`: two files of the same bytes under
// different names are two entries of the data, kept and said; a shape `--resample` cannot remesh is kept at
// its own resolution and said with the reason. Each experiment runs through the CLI on small generated
// meshes, and both notes must reach stderr, the report and the JSON summary. Before, `experiment paper` said
// no same-content pair, and `noise`, `pose` and `topkids` said neither note (the remesh fallback only as a
// progress line and a table cell).
#include <gtest/gtest.h>

#include <filesystem>
#include <nlohmann/json.hpp>
#include <sstream>

#include "cshapes/support/atomic_file.h"
#include "cshapes/mesh/io.h"
#include "tests/test_support.h"

namespace cshapes {
namespace trust_experiments_test {

namespace fs = std::filesystem;

std::string q(const std::string& path) {
  return "'" + path + "'";
}

bool contains(const std::string& text, const std::string& part) {
  return text.find(part) != std::string::npos;
}

// The mesh with 100 tiny tetrahedra floating beside it (dust, as a scan may hold): every component keeps at
// least its 4 vertices, so no remesh reaches fewer than 400 vertices ("cannot be remeshed" at 300), while
// each method keeps the largest component and measures the shape.
Mesh with_dust(const Mesh& m) {
  const Eigen::RowVector3d lo = m.V.colwise().minCoeff(), hi = m.V.colwise().maxCoeff();
  const double step = (hi - lo).norm() / 50;
  const Index n = m.num_vertices(), nf = m.num_faces();
  Mesh out{Points(n + 400, 3), Faces(nf + 400, 3)};
  out.V.topRows(n) = m.V;
  out.F.topRows(nf) = m.F;
  const int corner_faces[4][3] = {{0, 2, 1}, {0, 1, 3}, {1, 2, 3}, {0, 3, 2}};
  for (int k = 0; k < 100; ++k) {
    const Eigen::RowVector3d at(hi.x() + step * (1 + k % 10), lo.y() + step * (k / 10), lo.z());
    const Index b = n + 4 * k;
    out.V.row(b) = at;
    for (int d = 0; d < 3; ++d) {
      Eigen::RowVector3d corner = at;
      corner[d] += step / 3;
      out.V.row(b + 1 + d) = corner;
    }
    for (int f = 0; f < 4; ++f)
      for (int c = 0; c < 3; ++c) out.F(nf + 4 * k + f, c) = static_cast<int>(b + corner_faces[f][c]);
  }
  return out;
}

// A folder of meshes (no manifest: the class is the file name without digits): 2 classes × 3 generated
// poses of 400 vertices (poses of a class share their faces), biped7.off a byte copy of biped1.off, and
// dust0.off (biped0 with dust, a class of its own). Returns the folder.
std::string data_with_copy_and_dust(const std::string& dir) {
  const std::string data = dir + "/data";
  fs::remove(test::generated_dataset(data, 2, 3, 400));
  fs::copy_file(data + "/biped1.off", data + "/biped7.off");
  write_mesh(data + "/dust0.off", with_dust(read_mesh(data + "/biped0.off")));
  return data;
}

// The two notes in a JSON summary's failures: biped7 kept as the same content as biped1 (stage "dataset"),
// dust0 kept at its own resolution with the remesher's reason (stage "resample"); neither left out.
void expect_notes_in_json(const nlohmann::json& failures, const std::string& copy, const std::string& first,
                          const std::string& dusty, const std::string& where) {
  SCOPED_TRACE(where);
  bool same = false, kept = false;
  for (const auto& f : failures) {
    if (f["name"] == copy && f["stage"] == "dataset") {
      same = true;
      EXPECT_FALSE(f["left_out"].get<bool>()) << f.dump();
      EXPECT_TRUE(contains(f["reason"].get<std::string>(), "the same content as " + first)) << f.dump();
    }
    if (f["name"] == dusty && f["stage"] == "resample") {
      kept = true;
      EXPECT_FALSE(f["left_out"].get<bool>()) << f.dump();
      EXPECT_TRUE(contains(f["fallback"].get<std::string>(), "kept at its own resolution: cannot be remeshed"))
          << f.dump();
    }
  }
  EXPECT_TRUE(same) << failures.dump(2);
  EXPECT_TRUE(kept) << failures.dump(2);
}

// The same two notes on stderr and in a report's table of shapes left out and fallbacks.
void expect_notes_in_text(const std::string& err, const std::string& report, const std::string& copy,
                          const std::string& first, const std::string& dusty) {
  EXPECT_TRUE(contains(err, copy + ": the same content as " + first)) << err;
  EXPECT_TRUE(contains(err, dusty + ": not resampled to 300 vertices, kept at its own resolution: cannot be "
                                    "remeshed"))
      << err;
  EXPECT_TRUE(contains(report, "| dataset | the same content as " + first)) << report;
  EXPECT_TRUE(contains(report, "| resample | not resampled to 300 vertices, kept at its own resolution: "
                               "cannot be remeshed"))
      << report;
}

TEST(TrustExperiments, PaperSaysTheSameContentAndTheShapesNotResampled) {
  const std::string dir = test::scratch_dir("trust-exp-paper");
  const std::string data = data_with_copy_and_dust(dir), out = dir + "/out";
  const test::CliResult r = test::run_cli(
      "experiment paper --data " + q(data) + " --out " + q(out) +
      " --methods cmds --resample 300 --poses-per-class all --noisy-per-class 0 --no-table1 --no-figure-data "
      "--no-draw --correspondence-samples 0 --json");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const nlohmann::json j = nlohmann::json::parse(r.out);
  EXPECT_EQ(j["shapes"], 8);  // both copies stay queries, and so does the shape kept as it is
  expect_notes_in_json(j["failures"], "biped7", "biped1", "dust0", "stdout");
  expect_notes_in_json(nlohmann::json::parse(read_file(out + "/metrics.json"))["failures"], "biped7", "biped1",
                       "dust0", "metrics.json");
  expect_notes_in_text(r.err, read_file(out + "/report.md"), "biped7", "biped1", "dust0");
  fs::remove_all(dir);
}

TEST(TrustExperiments, NoiseSaysTheSameContentAndTheShapesNotResampled) {
  const std::string dir = test::scratch_dir("trust-exp-noise");
  const std::string data = data_with_copy_and_dust(dir), out = dir + "/out";
  const test::CliResult r = test::run_cli("experiment noise --data " + q(data) + " --out " + q(out) +
                                          " --methods cmds --levels 0,1 --resample 300 --no-draw --json");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const nlohmann::json j = nlohmann::json::parse(r.out);
  EXPECT_EQ(j["poses"], 8);
  expect_notes_in_json(j["failures"], "biped7", "biped1", "dust0", "stdout");
  expect_notes_in_json(nlohmann::json::parse(read_file(out + "/noise.json"))["failures"], "biped7", "biped1",
                       "dust0", "noise.json");
  expect_notes_in_text(r.err, read_file(out + "/report.md"), "biped7", "biped1", "dust0");
  fs::remove_all(dir);
}

// experiment pose: stderr, pose.md and, with --json, its JSON summary.
TEST(TrustExperiments, PoseSaysTheSameContentAndTheShapesNotResampled) {
  const std::string dir = test::scratch_dir("trust-exp-pose");
  const std::string data = data_with_copy_and_dust(dir), out = dir + "/out";
  const test::CliResult r =
      test::run_cli("experiment pose --data " + q(data) + " --out " + q(out) +
                    " --methods cmds --resample 300 --samples 100 --stress-sources 2 --no-parts --no-draw");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  // Both copies are poses: their pair with each other and with every other biped is measured.
  const std::string pairs = read_file(out + "/pose_pairs.csv");
  EXPECT_TRUE(contains(pairs, "biped1,biped7,biped,cmds")) << pairs;
  expect_notes_in_text(r.err, read_file(out + "/pose.md"), "biped7", "biped1", "dust0");
  EXPECT_TRUE(contains(r.out, "| dataset | the same content as biped1")) << r.out;  // pose.md on stdout too
  // --json: the summary and the failures as JSON on stdout, from the cache.
  const test::CliResult j =
      test::run_cli("-q experiment pose --data " + q(data) + " --out " + q(out) +
                    " --methods cmds --resample 300 --samples 100 --stress-sources 2 --no-parts --no-draw --json");
  ASSERT_EQ(j.exit_code, 0) << j.err;
  const nlohmann::json summary = nlohmann::json::parse(j.out);
  EXPECT_GT(summary.at("pairs").get<int>(), 0);
  bool cmds_all = false;
  for (const nlohmann::json& row : summary.at("summary"))
    cmds_all = cmds_all || (row.at("form") == "cmds" && row.at("class") == "all" &&
                            row.at("median_rms").get<double>() > 0);
  EXPECT_TRUE(cmds_all) << summary.dump(2);
  expect_notes_in_json(summary.at("failures"), "biped7", "biped1", "dust0", "stdout");
  fs::remove_all(dir);
}

// A TOPKIDS-style folder: reference ref.off, query poses a, b (a byte copy of a) and dust (the reference
// with dust), each with identity ground truth over the reference's vertices.
TEST(TrustExperiments, TopkidsSaysTheSameContentAndTheShapesNotResampled) {
  const std::string dir = test::scratch_dir("trust-exp-topkids");
  const std::string generated = dir + "/generated", data = dir + "/kids", out = dir + "/out";
  test::generated_dataset(generated, 1, 2, 400);
  fs::create_directories(data);
  fs::copy_file(generated + "/biped0.off", data + "/ref.off");
  fs::copy_file(generated + "/biped1.off", data + "/a.off");
  fs::copy_file(generated + "/biped1.off", data + "/b.off");
  const Mesh reference = read_mesh(data + "/ref.off");
  write_mesh(data + "/dust.off", with_dust(reference));
  std::ostringstream truth;
  for (Index v = 1; v <= reference.num_vertices(); ++v) truth << v << ' ' << v << '\n';
  for (const char* pose : {"a", "b", "dust"}) test::write_text(data + "/" + pose + "_ref.txt", truth.str());
  const test::CliResult r =
      test::run_cli("experiment topkids --data " + q(data) + " --out " + q(out) +
                    " --reference ref --methods cmds --samples 50 --resample 300 --no-draw --json");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const nlohmann::json j = nlohmann::json::parse(r.out);
  EXPECT_EQ(j["poses"], 3);
  expect_notes_in_json(j["failures"], "b", "a", "dust", "stdout");
  expect_notes_in_json(nlohmann::json::parse(read_file(out + "/topkids.json"))["failures"], "b", "a", "dust",
                       "topkids.json");
  expect_notes_in_text(r.err, read_file(out + "/report.md"), "b", "a", "dust");
  fs::remove_all(dir);
}

}  // namespace trust_experiments_test
}  // namespace cshapes
