// The CLI's error contract: a bad input gives a non-zero exit and ONE line on stderr naming the file, and a
// failed command leaves no output file behind.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <nlohmann/json.hpp>

#include "cshapes/mesh/io.h"
#include "cshapes/data/synthetic.h"
#include "tests/test_support.h"

namespace cshapes {
namespace cli_errors_test {

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
  fs::create_directories(dir + "/out");  // an output file's folder must exist (CliOutput.AMissingFolder...)
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

// The exit codes of README's table.
constexpr int kData = 1, kUsage = 2;

// A refusal: no signal, the exit code of the table, and one line "cshapes <command>: error: ..." that names
// every needle (the option or the file).
void expect_refusal(const test::CliResult& result, int code, const std::string& command,
                    const std::vector<std::string>& needles) {
  EXPECT_GE(result.exit_code, 0) << "killed by a signal: " << result.err;
  EXPECT_EQ(result.exit_code, code) << result.err;
  EXPECT_EQ(std::count(result.err.begin(), result.err.end(), '\n'), 1) << result.err;
  EXPECT_EQ(result.err.rfind("cshapes " + command + ": error: ", 0), 0u) << result.err;
  for (const std::string& needle : needles)
    EXPECT_NE(result.err.find(needle), std::string::npos) << result.err;
}

// Inputs on which any work would take long, so that a refusal must come before it: a 501,264-vertex grid
// (all-pairs geodesics: 1 TB; Coulomb: minutes) and a regular tetrahedron (remeshed to a huge count).
struct Inputs {
  std::string dir, big, tetra;
};
const Inputs& inputs() {
  static const Inputs in = [] {
    Inputs i;
    i.dir = test::scratch_dir("cli-refusals");
    i.big = i.dir + "/big.ply";
    WriteOptions binary;
    binary.binary = true;
    write_mesh(i.big, grid(708, 708), binary);
    i.tetra = i.dir + "/tetra.off";
    test::write_text(i.tetra, std::string("OFF\n4 4 6\n1 1 1\n1 -1 -1\n-1 1 -1\n-1 -1 1\n") +
                                  "3 0 1 2\n3 0 3 1\n3 0 2 3\n3 1 3 2\n");
    return i;
  }();
  return in;
}
std::string q(const std::string& path) {
  return "'" + path + "'";
}

TEST(CliRefusals, ParserErrorsInTheCommonFormat) {
  const Inputs& in = inputs();
  // CLI11's NonNegativeNumber printed a 300-digit range here.
  test::CliResult r = test::run_cli("--threads -1 info " + q(in.tetra));
  expect_refusal(r, kUsage, "info", {"--threads", "expected an integer >= 0", "'-1'"});
  EXPECT_LT(r.err.size(), 200u) << r.err;
  // CLI11 said "not in range" for a word.
  expect_refusal(test::run_cli("--threads abc info " + q(in.tetra)), kUsage, "info", {"--threads", "'abc'"});
  expect_refusal(test::run_cli("canon " + q(in.big) + " -o x.ply --bogus"), kUsage, "canon", {"--bogus"});
  expect_refusal(test::run_cli("remesh " + q(in.tetra) + " -o x.off"), kUsage, "remesh", {"--vertices"});
  expect_refusal(test::run_cli("geodesics " + q(in.big) + " -o d.bin --method bogus"), kUsage, "geodesics",
                 {"--method", "expected one of", "'bogus'"});
  expect_refusal(test::run_cli("canon " + q(in.big) + " -o x.ply --method coulomb --coulomb-tolerance x1"),
                 kUsage, "canon", {"--coulomb-tolerance", "'x1'"});
  expect_refusal(test::run_cli("bench coulomb --repeats 0"), kUsage, "bench coulomb", {"--repeats"});
}

TEST(CliRefusals, ThreadsBeyondFourPerCoreAreCappedWithAWarning) {
  // 65,536 threads crashed inside the OpenMP runtime (the float direct Coulomb sum).
  const Inputs& in = inputs();
  const std::string out = in.dir + "/threads.ply";
  test::CliResult r = test::run_cli("-q --threads 65536 canon " + q(in.tetra) + " -o " + q(out) +
                                    " --method coulomb --coulomb-summation direct-float");
  EXPECT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
  EXPECT_EQ(r.err.rfind("cshapes canon: warning: --threads 65536", 0), 0u) << r.err;
  EXPECT_TRUE(fs::exists(out));
}

TEST(CliRefusals, CountsAndSizesBeforeAnyWork) {
  const Inputs& in = inputs();
  // A negative count reached CGAL's unsigned iteration count and never ended.
  expect_refusal(test::run_cli("remesh " + q(in.tetra) + " -o " + q(in.dir + "/r.off") +
                               " --vertices 30 --iterations -3"),
                 kUsage, "remesh", {"--iterations", "'-3'"});
  // Memory grew at 130 MB/s: the estimate is refused up front, and named.
  expect_refusal(
      test::run_cli("remesh " + q(in.tetra) + " -o " + q(in.dir + "/r.off") + " --vertices 10000000000"),
      kData, "remesh", {"--vertices 10000000000", "GB", "available"});
  expect_refusal(test::run_cli("geodesics " + q(in.big) + " -o " + q(in.dir + "/d.bin")), kData, "geodesics",
                 {"501264", "GB", "available"});
  // The full matrix asked for by name is refused; landmark rows too many for memory are refused too (auto
  // takes 300 landmark rows here and succeeds, in about a minute: not run).
  expect_refusal(test::run_cli("canon " + q(in.big) + " -o " + q(in.dir + "/c.ply") +
                               " --method cmds --mds-solver full"),
                 kData, "canon", {"501264", "GB"});
  expect_refusal(test::run_cli("canon " + q(in.big) + " -o " + q(in.dir + "/c.ply") +
                               " --method smacof --mds-solver landmarks --mds-landmarks 200000"),
                 kData, "canon", {"501264", "GB"});
  for (const std::string option : {"--projection-steps -1", "--coulomb-max-iterations -1", "--tear-times -2",
                                   "--coulomb-window 0", "--knn 0", "--step-factor 0", "--momentum 1"})
    expect_refusal(test::run_cli("canon " + q(in.big) + " -o x.ply --method coulomb " + option), kUsage,
                   "canon", {option.substr(0, option.find(' '))});
  expect_refusal(test::run_cli("canon " + q(in.big) + " -o x.ply --method smacof --smacof-max-iterations -5"),
                 kUsage, "canon", {"--smacof-max-iterations"});
}

TEST(CliRefusals, OptionsOfAnotherMethodAreRefusedByName) {
  const Inputs& in = inputs();
  const std::string canon = "canon " + q(in.big) + " -o " + q(in.dir + "/c.ply");
  expect_refusal(test::run_cli(canon + " --method coulomb --accelerate rre"), kUsage, "canon",
                 {"--accelerate applies to --method smacof only"});
  expect_refusal(test::run_cli(canon + " --method coulomb --distances d.bin"), kUsage, "canon",
                 {"--distances applies to --method cmds or smacof only, not coulomb"});
  // Issue 36: spectral-mds reads --geodesics of the cmds group, not its other options (they were ignored,
  // the output byte-identical to the default run), nor lbo's --eigenpairs; --history is refused for the
  // methods without iterations.
  for (const std::string option :
       {"--distances d.bin", "--mds-solver full", "--mds-landmarks 50", "--eigenpairs 12"}) {
    const std::string name = option.substr(0, option.find(' '));
    expect_refusal(test::run_cli(canon + " --method spectral-mds " + option), kUsage, "canon",
                   {name + " applies to --method ", "only, not spectral-mds"});
  }
  expect_refusal(test::run_cli(canon + " --method coulomb --mds-solver full"), kUsage, "canon",
                 {"--mds-solver applies to --method cmds or smacof only, not coulomb"});
  // The fold repair of landmark forms is SMACOF's: classical MDS interpolates without one (it was ignored).
  expect_refusal(test::run_cli(canon + " --method cmds --fold-overstretch 2"), kUsage, "canon",
                 {"--fold-overstretch applies to --method smacof only, not cmds"});
  for (const char* method : {"cmds", "lbo", "diffusion", "spectral-mds"})
    expect_refusal(test::run_cli(canon + " --method " + method + " --history " + q(in.dir + "/h.csv")),
                   kUsage, "canon", {"--history applies to --method coulomb or smacof only"});
  expect_refusal(test::run_cli(canon + " --method smacof --scheme paper"), kUsage, "canon",
                 {"--scheme applies to --method coulomb only"});
  expect_refusal(test::run_cli(canon + " --method smacof --tear-fraction 0.1"), kUsage, "canon",
                 {"--tear-fraction applies to --method coulomb only"});
  expect_refusal(test::run_cli(canon + " --method cmds --smacof-max-iterations 5"), kUsage, "canon",
                 {"--smacof-max-iterations applies to --method smacof only"});
  // ... and options that only one setting of another option reads.
  expect_refusal(test::run_cli(canon + " --method coulomb --fixed-step 0.1"), kUsage, "canon",
                 {"--fixed-step applies to --step-rule fixed only"});
  expect_refusal(test::run_cli(canon + " --method smacof --smacof-window 4"), kUsage, "canon",
                 {"--smacof-window applies to --accelerate rre or mpe only"});
  expect_refusal(test::run_cli("geodesics " + q(in.big) + " -o d.bin --method fmm --heat-mode direct"),
                 kUsage, "geodesics", {"--heat-mode applies to --method heat or heat-cgal only"});
  // distmat too, before it reads anything (here a missing folder it never gets to).
  const std::string missing = in.dir + "/no-such-dataset";
  expect_refusal(test::run_cli("-q distmat " + q(missing) + " -o " + q(in.dir + "/D.csv") +
                               " --method coulomb --accelerate rre"),
                 kUsage, "distmat", {"--accelerate applies to --method smacof only"});
}

TEST(CliRefusals, OutputPathsAreCheckedBeforeAnyWork) {
  const Inputs& in = inputs();
  const std::string canon = "canon " + q(in.big) + " --method coulomb -o ";
  expect_refusal(test::run_cli(canon + q(in.dir + "/x.stl")), kUsage, "canon", {"x.stl", ".off, .ply"});
  expect_refusal(test::run_cli(canon + q(in.dir + "/noextension")), kUsage, "canon",
                 {"noextension", "no file extension"});
  expect_refusal(test::run_cli(canon + q(in.tetra + "/x.ply")), kUsage, "canon", {"x.ply", "not a folder"});
  expect_refusal(test::run_cli(canon + "/proc/cshapes-test/x.ply"), kUsage, "canon",
                 {"/proc/cshapes-test/x.ply"});
  expect_refusal(test::run_cli(canon + q(in.dir + "/c.ply") + " --history " + q(in.dir + "/h.txt")), kUsage,
                 "canon", {"h.txt", ".csv"});
  expect_refusal(test::run_cli("geodesics " + q(in.big) + " -o " + q(in.dir + "/d.csv")), kUsage, "geodesics",
                 {"d.csv", ".bin"});
  expect_refusal(
      test::run_cli("remesh " + q(in.tetra) + " --vertices 10000000000 -o " + q(in.dir + "/r.stl")), kUsage,
      "remesh", {"r.stl"});
  expect_refusal(test::run_cli("noise " + q(in.big) + " -o " + q(in.dir + "/n.ply") + " --pairs-json " +
                               q(in.dir + "/p.csv")),
                 kUsage, "noise", {"p.csv", ".json"});
  expect_refusal(test::run_cli("distmat " + q(in.dir) + " -o " + q(in.dir + "/D.txt")), kUsage, "distmat",
                 {"D.txt", ".csv"});
  // Nothing was written.
  EXPECT_FALSE(fs::exists(in.dir + "/x.stl"));
  EXPECT_FALSE(fs::exists("/proc/cshapes-test"));
}

TEST(CliRefusals, AMissingFileReadsTheSameInEveryCommand) {
  const Inputs& in = inputs();
  const std::string missing = in.dir + "/missing.off";
  std::vector<std::string> messages;
  for (const std::string command : {"canon", "geodesics", "remesh", "noise", "info", "align"}) {
    std::string arguments = command + " " + q(missing);
    if (command == "align") arguments += " " + q(in.tetra);
    if (command == "remesh") arguments += " --vertices 100";
    if (command != "info" && command != "align") arguments += " -o " + q(in.dir + "/out-" + command + ".ply");
    if (command == "geodesics") arguments = "geodesics " + q(missing) + " -o " + q(in.dir + "/d.bin");
    SCOPED_TRACE(arguments);
    test::CliResult r = test::run_cli(arguments);
    expect_refusal(r, kData, command, {missing});
    messages.push_back(r.err.substr(r.err.find(": error: ")));
  }
  for (const std::string& m : messages) EXPECT_EQ(m, messages.front());
}

TEST(CliRefusals, NumbersAndListsAreParsedStrictly) {
  // Issue 22: `--poses-per-class 2abc`, `2.7` and `1e400` were taken as 2, 2 and 1; `--levels 1,,2` was
  // accepted; `topkids --poses ''` and `pose --shapes ''` meant "all".
  const Inputs& in = inputs();
  const std::string out = q(in.dir + "/exp");
  for (const std::string value : {"2abc", "2.7", "1e400", "0", "''"})
    for (const std::string experiment : {"noise", "paper"})
      expect_refusal(test::run_cli("experiment " + experiment + " --data " + q(in.dir) + " --out " + out +
                                   " --poses-per-class " + value),
                     kUsage, "experiment " + experiment, {"--poses-per-class", "or 'all'"});
  expect_refusal(
      test::run_cli("experiment paper --data " + q(in.dir) + " --out " + out + " --noisy-per-class 1e400"),
      kUsage, "experiment paper", {"--noisy-per-class", "'1e400'"});
  expect_refusal(test::run_cli("experiment noise --data " + q(in.dir) + " --out " + out + " --levels 1,,2"),
                 kUsage, "experiment noise", {"--levels", "empty item"});
  expect_refusal(test::run_cli("experiment topkids --data " + q(in.dir) + " --out " + out + " --poses ''"),
                 kUsage, "experiment topkids", {"--poses", "empty list"});
  expect_refusal(test::run_cli("experiment pose --data " + q(in.dir) + " --out " + out + " --shapes ''"),
                 kUsage, "experiment pose", {"--shapes", "empty list"});
  expect_refusal(test::run_cli("experiment pose --data " + q(in.dir) + " --out " + out + " --shapes a,"),
                 kUsage, "experiment pose", {"--shapes", "empty item"});
}

TEST(CliRefusals, HelpAndChecksAgreeAndOptionsThatDoNotApplyAreRefused) {
  const Inputs& in = inputs();
  // Issue 22: `noise --min-ratio 0.5` said "must be >= 1" after the help said ">= 0".
  expect_refusal(test::run_cli("noise " + q(in.tetra) + " -o " + q(in.dir + "/n.off") + " --min-ratio 0.5"),
                 kUsage, "noise", {"--min-ratio", ">= 1", "'0.5'"});
  const test::CliResult help = test::run_cli("noise --help");
  const size_t at = help.out.find("--min-ratio");
  ASSERT_NE(at, std::string::npos) << help.out;
  EXPECT_NE(help.out.substr(at, help.out.find('\n', at) - at).find(">= 1"), std::string::npos) << help.out;
  // Issue 22: `canon --knn 5` on a triangle mesh and `--tear-after 5 --tear-fraction 0` were accepted.
  expect_refusal(test::run_cli("canon " + q(in.tetra) + " -o " + q(in.dir + "/c.ply") + " --knn 5"), kUsage,
                 "canon", {"--knn applies to point clouds", in.tetra});
  expect_refusal(test::run_cli("canon " + q(in.tetra) + " -o " + q(in.dir + "/c.ply") +
                               " --tear-after 5 --tear-fraction 0"),
                 kUsage, "canon", {"--tear-after applies only when tearing"});
  // ... on every command: distmat and the experiments warned and went on ("ignored: no method run here").
  expect_refusal(test::run_cli("distmat " + q(in.dir) + " -o " + q(in.dir + "/D.csv") +
                               " --method cmds --tear-fraction 0.1"),
                 kUsage, "distmat", {"--tear-fraction applies to --method coulomb only"});
  expect_refusal(test::run_cli("experiment paper --data " + q(in.dir) + " --out " + q(in.dir + "/p") +
                               " --methods cmds,smacof --scheme paper"),
                 kUsage, "experiment paper", {"--scheme applies to method coulomb only", "(cmds,smacof)"});
  EXPECT_FALSE(fs::exists(in.dir + "/p"));
}

TEST(CliPointClouds, EveryMethodReadsKnn) {
  // --knn was an option of the coulomb group only: `--method lbo --knn 12` was refused ("applies to --method
  // coulomb only") while lbo's own error on a disconnected graph said "raise --knn". Two clusters of 60
  // points on two unit circles' worth of a sphere far apart: k = 8 cannot join them; every method says so
  // and names k; no k joins them, so each method's refusal proves it read the k given.
  const std::string dir = test::scratch_dir("cli-knn");
  std::string xyz;
  for (int c = 0; c < 2; ++c)
    for (int i = 0; i < 60; ++i) {
      const double t = 2 * M_PI * i / 60, z = std::cos(7.0 * i);
      xyz += std::to_string(10.0 * c + std::cos(t) * std::sqrt(1 - z * z)) + " " +
             std::to_string(std::sin(t) * std::sqrt(1 - z * z)) + " " + std::to_string(z) + "\n";
    }
  test::write_text(dir + "/two.xyz", xyz);
  for (const char* method : {"coulomb", "cmds", "lbo", "diffusion"}) {
    const test::CliResult r = test::run_cli("canon " + q(dir + "/two.xyz") + " -o " + q(dir + "/c.ply") +
                                            " --method " + method + " --knn 11");
    EXPECT_EQ(r.exit_code, kData) << method << ": " << r.err;
    EXPECT_NE(r.err.find("11"), std::string::npos) << method << ": " << r.err;
    EXPECT_NE(r.err.find("--knn"), std::string::npos) << method << ": " << r.err;
    EXPECT_EQ(r.err.find("applies to"), std::string::npos) << method << ": " << r.err;
  }
  fs::remove_all(dir);
}

TEST(CliRefusals, TheReferenceIsReadBeforeAnyWork) {
  // Issue 22: `distmat --reference missing.csv` failed only after all the work.
  const std::string dir = test::scratch_dir("cli-reference");
  write_mesh(dir + "/data/ball0.off", icosphere(1, 1.0));
  write_mesh(dir + "/data/ball1.off", icosphere(1, 1.5));
  const test::CliResult r = test::run_cli(
      "distmat " + q(dir + "/data") + " -o " + q(dir + "/D.csv") + " --cache " + q(dir + "/cache") +
      " --method cmds --two-stage-k 1 --reference " + q(dir + "/missing.csv"));
  expect_refusal(r, kData, "distmat", {dir + "/missing.csv", "no such file"});  // one line: no shape note
  EXPECT_FALSE(fs::exists(dir + "/cache/forms"));
  fs::remove_all(dir);
}

TEST(CliRefusals, EvaluateChecksTheMatrixByItsStatedRules) {
  // Issue 22: `evaluate` accepted asymmetric, negative and non-zero-diagonal matrices, duplicate names.
  const std::string dir = test::scratch_dir("cli-evaluate");
  test::write_text(dir + "/negative.csv", "a0,a1,b0\n0,1,2\n1,0,-3\n2,-3,0\n");
  expect_refusal(test::run_cli("evaluate " + q(dir + "/negative.csv") + " --out " + q(dir + "/out1")), kData,
                 "evaluate", {"negative.csv", "'a1' to 'b0'", ">= 0"});
  test::write_text(dir + "/twice.csv", "a0,a1,a0\n0,1,2\n1,0,3\n2,3,0\n");
  expect_refusal(test::run_cli("evaluate " + q(dir + "/twice.csv") + " --out " + q(dir + "/out2")), kData,
                 "evaluate", {"'a0' appears twice"});
  test::write_text(dir + "/asymmetric.csv", "a0,a1,b0,b1\n0,1,2,2\n1,0,3,2\n2,3.5,0,1\n2,2,1,0.5\n");
  const test::CliResult r = test::run_cli("-q evaluate " + q(dir + "/asymmetric.csv") +
                                          " --min-class-size 2 --out " + q(dir + "/out3"));
  EXPECT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.err.find("warning: " + dir + "/asymmetric.csv: not symmetric"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("non-zero diagonal"), std::string::npos) << r.err;
  EXPECT_NE(test::run_cli("evaluate --help").out.find("refused: two shapes of one name"), std::string::npos);
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

}  // namespace cli_errors_test
}  // namespace cshapes
