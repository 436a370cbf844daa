// The CLI's error contract: a bad input gives a non-zero exit and ONE line on stderr naming the file, and a
// failed command leaves no output file behind.
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <nlohmann/json.hpp>

#include "tests/test_support.h"

namespace cshapes {
namespace {

namespace fs = std::filesystem;

const char* const kTetraFaces = "3 0 2 1\n3 0 1 3\n3 0 3 2\n3 1 2 3\n";

void expect_one_line_error(const test::CliResult& result, const std::string& path) {
  EXPECT_NE(result.exit_code, 0);
  EXPECT_EQ(std::count(result.err.begin(), result.err.end(), '\n'), 1) << result.err;
  EXPECT_NE(result.err.find(path), std::string::npos) << result.err;
}

TEST(CliErrors, BadOffFilesGiveOneLineNamingTheFile) {
  std::string dir = test::scratch_dir("cli-errors");
  struct Case {
    const char* name;
    std::string text;
  };
  const char png_like[] = "\x89PNG\r\n\x1a\n\x00\x01 garbage";
  const std::string garbage(png_like, sizeof png_like - 1);
  const Case cases[] = {
      {"truncated.off", "OFF\n4 4 6\n0 0 0\n1 0 0\n0 1 0\n"},
      {"nan.off", std::string("OFF\n4 4 6\n0 0 0\n1 0 nan\n0 1 0\n0 0 1\n") + kTetraFaces},
      {"index.off", "OFF\n4 4 6\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n3 0 2 1\n3 0 1 3\n3 0 3 7\n3 1 2 3\n"},
      {"garbage.off", garbage},
  };
  for (const Case& c : cases) {
    std::string path = dir + "/" + c.name;
    test::write_text(path, c.text);
    SCOPED_TRACE(path);
    expect_one_line_error(test::run_cli("info '" + path + "'"), path);
    expect_one_line_error(test::run_cli("info --json '" + path + "'"), path);
  }
  fs::remove_all(dir);
}

TEST(CliErrors, ConvertOfABadFileLeavesNoOutput) {
  std::string dir = test::scratch_dir("cli-errors");
  std::string bad = dir + "/bad.off", out = dir + "/out/converted.ply";
  test::write_text(bad, "OFF\n4 4 6\n0 0 0\n1 0 0\n");
  expect_one_line_error(test::run_cli("convert '" + bad + "' '" + out + "'"), bad);
  EXPECT_FALSE(fs::exists(out));
  if (fs::exists(dir + "/out")) {
    EXPECT_TRUE(fs::is_empty(dir + "/out"));
  }
  // The same command on a good file writes the output.
  std::string good = dir + "/good.off";
  test::write_text(good, std::string("OFF\n4 4 6\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n") + kTetraFaces);
  test::CliResult result = test::run_cli("convert '" + good + "' '" + out + "'");
  EXPECT_EQ(result.exit_code, 0) << result.err;
  EXPECT_TRUE(fs::exists(out));
  // Unknown output format: refused, nothing written.
  std::string stl = dir + "/out/converted.stl";
  expect_one_line_error(test::run_cli("convert '" + good + "' '" + stl + "'"), stl);
  EXPECT_FALSE(fs::exists(stl));
  fs::remove_all(dir);
}

TEST(CliErrors, InfoJsonOnCat0) {
  CSHAPES_REQUIRE_DATA();
  std::string cat = test::tosca5k("cat0");
  test::CliResult result = test::run_cli("info --json '" + cat + "'");
  ASSERT_EQ(result.exit_code, 0) << result.err;
  nlohmann::json j = nlohmann::json::parse(result.out);
  EXPECT_EQ(j["vertices"], 5000);
  EXPECT_EQ(j["euler_characteristic"], 2);
}

}  // namespace
}  // namespace cshapes
