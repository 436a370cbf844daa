// The CLI's partial-result exit code (3) and --strict: `experiment paper` and `distmat` on a small generated
// dataset with one shape every method fails on finish with the others, name the shape on stderr and in the
// JSON, and exit with 3; --strict stops at it with exit code 1. Each affected command documents the code in
// its --help.
#include <gtest/gtest.h>

#include <cctype>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>
#include <vector>

#include "cshapes/support/atomic_file.h"
#include "cshapes/mesh/io.h"
#include "cshapes/data/synthetic.h"
#include "cshapes/eval/distance_csv.h"
#include "test_support.h"

namespace cshapes {
namespace partial_results_cli_test {

// 2 classes × 3 poses of 400 vertices in a folder (no manifest: the class is the name without digits), plus
// CLASS9.off in the first class: readable, one component, but scaled to 1e150 with one vertex at 1e300, where
// every method's numbers leave the floating-point range (geodesics NaN or inf, Coulomb edges of infinite
// length).
std::string data_with_unusable_shape(const std::string& tag) {
  const std::string dir = test::scratch_dir(tag);
  test::CliResult r = test::run_cli("-q generate dataset --out '" + dir +
                                    "/gen' --classes 2 --poses 3 --noisy 0 --vertices 400");
  EXPECT_EQ(r.exit_code, 0) << r.err;
  std::istringstream manifest(read_file(dir + "/gen/manifest.csv"));
  std::string line;
  std::getline(manifest, line);  // header: file first
  while (std::getline(manifest, line)) {
    const std::string file = line.substr(0, line.find(','));
    const Mesh m = read_mesh(dir + "/gen/" + file);
    write_mesh(dir + "/data/" + std::filesystem::path(file).filename().string(), m);
  }
  Mesh broken = icosphere(2);
  broken.V *= 1e150;
  broken.V.row(0).setConstant(1e300);
  std::string first_class;
  for (const auto& e : std::filesystem::directory_iterator(dir + "/data")) {
    std::string stem = e.path().stem().string();
    while (!stem.empty() && std::isdigit(static_cast<unsigned char>(stem.back()))) stem.pop_back();
    if (first_class.empty() || stem < first_class) first_class = stem;
  }
  write_mesh(dir + "/data/" + first_class + "9.off", broken);
  return dir;
}

TEST(PartialResultsCli, ExperimentPaperLeavesTheShapeOutAndExitsWithThree) {
  const std::string dir = data_with_unusable_shape("partial_paper");
  const std::string base = "experiment paper --data '" + dir +
                           "/data' --methods coulomb,cmds --poses-per-class all --noisy-per-class 0 "
                           "--no-table1 --no-figure-data --correspondence-samples 0 --coulomb-max-iterations 60 ";
  test::CliResult r = test::run_cli(base + "--out '" + dir + "/out' --json");
  EXPECT_EQ(r.exit_code, 3) << r.err;
  EXPECT_NE(r.err.find("9 left out: the coulomb canonical form failed"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("1 shape was left out: a partial result (exit code 3)"), std::string::npos) << r.err;
  const nlohmann::json j = nlohmann::json::parse(r.out);
  EXPECT_EQ(j["shapes"], 6);
  // The forms stopped at the short cap are kept and named "not converged" (not left out); one shape is left
  // out: its Coulomb form is computed (on a copy scaled to unit size) but reaches 1e300, and ICP cannot take it.
  const std::vector<nlohmann::json> left_out = test::left_out_failures(j);
  ASSERT_EQ(left_out.size(), 1u) << j.dump(2);
  EXPECT_EQ(left_out[0]["stage"], "alignment");
  EXPECT_NE(read_file(dir + "/out/report.md").find("## Shapes left out"), std::string::npos);

  // --strict: stops at the shape, a data error (1), not the partial code.
  r = test::run_cli("-q " + base + "--out '" + dir + "/strict' --strict");
  EXPECT_EQ(r.exit_code, 1) << r.err;
  EXPECT_NE(r.err.find("9.off"), std::string::npos) << r.err;

  r = test::run_cli("experiment paper --help");
  EXPECT_NE(r.out.find("3 a partial result"), std::string::npos) << r.out;
}

TEST(PartialResultsCli, DistmatLeavesTheShapeOutAndExitsWithThree) {
  const std::string dir = data_with_unusable_shape("partial_distmat");
  const std::string base =
      "distmat '" + dir + "/data' --method cmds -o '" + dir + "/d.csv' --cache '" + dir + "/cache'";
  test::CliResult r = test::run_cli(base + " --json");
  EXPECT_EQ(r.exit_code, 3) << r.err;
  const nlohmann::json j = nlohmann::json::parse(r.out);
  EXPECT_EQ(j["shapes"], 6);
  ASSERT_EQ(j["failures"].size(), 1u) << j.dump(2);
  EXPECT_EQ(j["failures"][0]["method"], "cmds");
  EXPECT_NE(r.err.find("left out: the cmds canonical form failed"), std::string::npos) << r.err;
  const NamedDistances D = read_distance_csv(dir + "/d.csv");  // the shape is not in the matrix
  EXPECT_EQ(D.names.size(), 6u);
  for (const std::string& name : D.names) EXPECT_NE(name.back(), '9') << name;
  r = test::run_cli(base + " --strict");
  EXPECT_EQ(r.exit_code, 1) << r.err;
  for (const char* command : {"distmat", "experiment noise", "experiment topkids", "experiment pose"}) {
    r = test::run_cli(std::string(command) + " --help");
    EXPECT_NE(r.out.find("3 a partial result"), std::string::npos) << command;
    EXPECT_NE(r.out.find("--strict"), std::string::npos) << command;
  }
}

}  // namespace partial_results_cli_test
}  // namespace cshapes
