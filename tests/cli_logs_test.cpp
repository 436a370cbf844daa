// The CLI in logs: progress written into a file or a pipe is plain lines (no "\r" fragments, no estimate in
// the first seconds of a stage), and a warning carries one prefix ("cshapes <command>: warning: …"), also
// under --quiet — including the library's warnings said on the note channel.
#include <gtest/gtest.h>

#include <filesystem>
#include <sstream>
#include <string>

#include "cshapes/support/atomic_file.h"
#include "cshapes/mesh/io.h"
#include "cshapes/data/synthetic.h"
#include "test_support.h"

namespace cshapes {
namespace cli_logs_test {

size_t count(const std::string& text, const std::string& what) {
  size_t n = 0;
  for (size_t at = text.find(what); at != std::string::npos; at = text.find(what, at + 1)) ++n;
  return n;
}

TEST(CliLogs, ProgressIntoAPipeIsPlainLines) {
  const std::string dir = test::scratch_dir("cli-logs-progress");
  write_mesh(dir + "/sphere.off", icosphere(3));
  const test::CliResult r =
      test::run_cli("canon '" + dir + "/sphere.off' -o '" + dir + "/form.ply' --method coulomb");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(r.err.find('\r'), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("[coulomb] 100.0% in "), std::string::npos) << "a stage's end is one line: " << r.err;
  EXPECT_EQ(r.err.find("s left"), std::string::npos) << "no estimate for a stage of a second: " << r.err;
}

TEST(CliLogs, AWarningHasOnePrefixEvenFromTheLibraryAndUnderQuiet) {
  const std::string dir = test::scratch_dir("cli-logs-warning");
  write_mesh(dir + "/coarse.off", icosphere(1));  // 42 vertices: the heat method warns that it is coarse
  for (const std::string quiet : {"", "-q "}) {
    const test::CliResult r = test::run_cli(quiet + "canon '" + dir + "/coarse.off' -o '" + dir +
                                            "/form.ply' --method cmds --geodesics heat");
    ASSERT_EQ(r.exit_code, 0) << r.err;
    EXPECT_EQ(count(r.err, "cshapes canon: warning: "), 1u) << r.err;
    EXPECT_EQ(count(r.err, "warning:"), 1u) << "one prefix: " << r.err;
  }
}

// Help everywhere: every command group is described, and every numeric option shows its default.
TEST(CliHelp, GroupsAreDescribedAndNumericOptionsShowTheirDefault) {
  const test::CliResult top = test::run_cli("--help");
  ASSERT_EQ(top.exit_code, 0);
  for (const std::string group : {"bench", "experiment", "generate"}) {
    const size_t at = top.out.find("\n  " + group + " ");
    ASSERT_NE(at, std::string::npos) << group;
    const std::string line = top.out.substr(at + 1, top.out.find('\n', at + 1) - at - 1);
    EXPECT_GT(line.size(), group.size() + 30) << "no description: " << line;
  }
  for (const std::string command :
       {"evaluate", "align", "canon", "distmat", "geodesics", "remesh", "noise", "experiment paper",
        "experiment noise", "experiment topkids", "experiment pose", "generate dataset", "stress"}) {
    const test::CliResult help = test::run_cli(command + " --help");
    ASSERT_EQ(help.exit_code, 0) << command;
    std::istringstream lines(help.out);
    for (std::string line; std::getline(lines, line);) {
      if (line.rfind("  -", 0) != 0 && line.rfind("    -", 0) != 0) continue;
      const bool numeric = line.find(" INT") != std::string::npos || line.find(" FLOAT") != std::string::npos;
      if (numeric && line.find("REQUIRED") == std::string::npos) {
        EXPECT_NE(line.find('='), std::string::npos) << command << ": no default shown: " << line;
      }
    }
  }
}

// `geodesics`: the output's form follows -o's extension (the help says CSV goes with --source).
TEST(CliOutput, GeodesicsWritesTheFormItsOutputNames) {
  const std::string dir = test::scratch_dir("cli-geodesics-output");
  write_mesh(dir + "/sphere.off", icosphere(2));
  const test::CliResult row =
      test::run_cli("-q geodesics '" + dir + "/sphere.off' --source 0 -o '" + dir + "/row.csv' --method fmm");
  ASSERT_EQ(row.exit_code, 0) << row.err;
  EXPECT_EQ(read_file(dir + "/row.csv").rfind("vertex,distance\n0,0", 0), 0u);
  const test::CliResult mixed =
      test::run_cli("-q geodesics '" + dir + "/sphere.off' --source 0 -o '" + dir + "/row.bin'");
  EXPECT_EQ(mixed.exit_code, 2);
  EXPECT_NE(mixed.err.find("-o NAME.csv"), std::string::npos) << mixed.err;
  const test::CliResult all_as_csv =
      test::run_cli("-q geodesics '" + dir + "/sphere.off' -o '" + dir + "/all.csv'");
  EXPECT_EQ(all_as_csv.exit_code, 2);
  EXPECT_NE(all_as_csv.err.find("needs --source"), std::string::npos) << all_as_csv.err;
}

// An output file's folder must exist: a mistyped folder is refused before any work, never created.
TEST(CliOutput, AMissingFolderOfAnOutputFileIsRefusedNotCreated) {
  const std::string dir = test::scratch_dir("cli-missing-folder");
  write_mesh(dir + "/sphere.off", icosphere(1));
  const test::CliResult r = test::run_cli("-q canon '" + dir + "/sphere.off' -o '" + dir + "/nowhere/x.ply'");
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find(dir + "/nowhere does not exist"), std::string::npos) << r.err;
  EXPECT_FALSE(std::filesystem::exists(dir + "/nowhere"));
}

}  // namespace cli_logs_test
}  // namespace cshapes
