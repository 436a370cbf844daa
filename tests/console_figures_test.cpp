// Numbers the CLI prints for people: three significant figures with a unit or a reference (a length with its
// share of the bounding-box diagonal or in mean edge lengths, a time in seconds), retrieval measures with the
// field's three decimals. --json, CSV and report files keep every digit and are not read here.
#include <gtest/gtest.h>

#include <regex>
#include <string>
#include <vector>

#include "cshapes/support/format.h"
#include "cshapes/support/progress.h"
#include "test_support.h"

namespace cshapes {
namespace console_figures_test {

std::string q(const std::string& path) {
  return "'" + path + "'";
}

// Significant digits of a printed number: "0.0138" → 3, "39.5" → 3, "3.441" → 4, "1.23e+05" → 3.
int significant_digits(const std::string& number) {
  std::string digits;
  for (const char c : number.substr(0, number.find_first_of("eE")))
    if (c >= '0' && c <= '9') digits += c;
  const size_t first = digits.find_first_not_of('0');
  return first == std::string::npos ? 1 : static_cast<int>(digits.size() - first);
}

// The groups of the first match of `pattern` in `text`; fails the test when there is none.
std::smatch find(const std::string& text, const std::string& pattern) {
  std::smatch m;
  EXPECT_TRUE(std::regex_search(text, m, std::regex(pattern))) << pattern << " not in:\n" << text;
  return m;
}

void expect_three_figures(const std::smatch& m, const std::string& where) {
  for (size_t i = 1; i < m.size(); ++i)
    EXPECT_LE(significant_digits(m[i].str()), 3) << m[i].str() << " in " << where << ": " << m[0].str();
}

const std::string kNumber = R"(([0-9.e+-]+))";

TEST(ConsoleFigures, SecondsTextHasThreeFiguresAndItsUnit) {
  EXPECT_EQ(seconds_text(5.1342), "5.13 s");
  EXPECT_EQ(seconds_text(0.013812), "0.0138 s");
  EXPECT_EQ(seconds_text(98.553), "98.6 s");
  EXPECT_EQ(seconds_text(4677.3), "4677 s");  // whole seconds, not "4.68e+03 s"
}

TEST(ConsoleFigures, DurationsInTheUnitThatReadsBestAndCountsWithTheirNouns) {
  EXPECT_EQ(duration_text(46.81), "46.8 s");
  EXPECT_EQ(duration_text(0.2083), "208 ms");
  EXPECT_EQ(duration_text(0.000111), "111 µs");
  EXPECT_EQ(counted(1, "glue"), "1 glue");
  EXPECT_EQ(counted(2, "glue"), "2 glues");
  EXPECT_EQ(counted(0, "iteration"), "0 iterations");
  EXPECT_EQ(counted(1, "vertex", "vertices"), "1 vertex");
  EXPECT_EQ(counted(3, "vertex", "vertices"), "3 vertices");
}

TEST(ConsoleFigures, CountsAreGroupedAndTheirNounsAgree) {
  EXPECT_EQ(grouped(0), "0");
  EXPECT_EQ(grouped(999), "999");
  EXPECT_EQ(grouped(1000), "1,000");
  EXPECT_EQ(grouped(22738), "22,738");
  EXPECT_EQ(grouped(1234567), "1,234,567");
  EXPECT_EQ(grouped(-1234), "-1,234");
  EXPECT_EQ(counted(50, "iteration"), "50 iterations");
  EXPECT_EQ(counted(5000, "point"), "5,000 points");
  EXPECT_EQ(counted(22738, "vertex", "vertices"), "22,738 vertices");
}

// The time left a progress report gives (the CLI's line and Python's progress=): none until 3 s and 5% of
// the stage, none once it is done.
TEST(ConsoleFigures, TimeLeftOnlyOnceTheEstimateMeansSomething) {
  EXPECT_FALSE(seconds_left_estimate(2.9, 0.5));
  EXPECT_FALSE(seconds_left_estimate(10, 0.04));
  EXPECT_FALSE(seconds_left_estimate(10, 1.0));
  ASSERT_TRUE(seconds_left_estimate(3, 0.25));
  EXPECT_DOUBLE_EQ(*seconds_left_estimate(3, 0.25), 9);
}

// A renamed stage reports under its new name, and a poll stays a poll.
TEST(ConsoleFigures, ARenamedStageKeepsPollsAsPolls) {
  std::vector<std::string> stages;
  const ProgressFn renamed = renamed_stage(
      [&](const std::string& stage, double, double) { stages.push_back(stage); }, "distances, Coulomb");
  renamed("distances", 1, 2);
  renamed("", 0, 0);
  EXPECT_EQ(stages, (std::vector<std::string>{"distances, Coulomb", ""}));
  EXPECT_FALSE(renamed_stage({}, "x"));
}

// align: R to three decimals, t and the distances to three significant figures, counts with their nouns;
// canon --method diffusion: its time and energy to three figures (it printed "t = 1.000000/λ1 = 3067.026961").
TEST(ConsoleFigures, AlignAndTheDiffusionMapPrintThreeFigures) {
  const std::string dir = test::scratch_dir("console-figures-align");
  ASSERT_EQ(test::run_cli("-q generate swissroll -o " + q(dir + "/roll.off")).exit_code, 0);
  const test::CliResult canon = test::run_cli("canon " + q(dir + "/roll.off") + " -o " + q(dir + "/d.ply") +
                                              " --method diffusion");
  ASSERT_EQ(canon.exit_code, 0) << canon.err;
  expect_three_figures(find(canon.err, "t = " + kNumber + "/λ1 = " + kNumber + "; 3 axes keep " + kNumber + "%"),
                       "diffusion");
  ASSERT_EQ(test::run_cli("-q canon " + q(dir + "/roll.off") + " -o " + q(dir + "/l.ply") + " --method lbo")
                .exit_code,
            0);
  const test::CliResult r = test::run_cli("align " + q(dir + "/d.ply") + " " + q(dir + "/l.ply"));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const std::smatch rows = find(r.out, R"(R +(-?\d\.\d{3}) +(-?\d\.\d{3}) +(-?\d\.\d{3}) +t +)" + kNumber);
  EXPECT_LE(significant_digits(rows[4].str()), 3) << rows[0].str();
  expect_three_figures(find(r.out, R"(diagonal, )" + kNumber + R"(\):)"), "align");
  find(r.out, R"(icp: (1 iteration|[02-9]\d* iterations|1\d+ iterations) on all points \(\d+ in all, (1 start|\d+ starts)\))");
  EXPECT_EQ(r.out.find("0.000000"), std::string::npos) << r.out;
}

TEST(ConsoleFigures, RemeshGivesLengthsWithTheirShareOfTheDiagonalAndAnglesInDegrees) {
  const std::string dir = test::scratch_dir("console-figures-remesh");
  ASSERT_EQ(test::run_cli("-q generate swissroll -o " + q(dir + "/roll.off")).exit_code, 0);
  const test::CliResult r =
      test::run_cli("remesh " + q(dir + "/roll.off") + " -o " + q(dir + "/out.off") + " --vertices 500");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  expect_three_figures(find(r.out, "hausdorff +" + kNumber + R"( \()" + kNumber + "% of the bbox diagonal " +
                                       kNumber + R"(\))"),
                       "remesh");
  expect_three_figures(find(r.out, "edge length +" + kNumber + R"( \()" + kNumber + "% of the bbox diagonal"),
                       "remesh");
  expect_three_figures(find(r.out, "min angle +" + kNumber + R"( deg \(input )" + kNumber +
                                       R"( deg\), mean smallest angle )" + kNumber + " deg"),
                       "remesh");
  // A stage's end in progress: seconds to three figures.
  expect_three_figures(find(r.err, R"(\[remesh\] 100\.0% in )" + kNumber + " s"), "progress");
}

TEST(ConsoleFigures, EvaluatePrintsRetrievalMeasuresWithThreeDecimals) {
  const std::string dir = test::scratch_dir("console-figures-evaluate");
  test::write_text(dir + "/m.csv",
                   "a0,a1,a2,b0,b1,b2\n0,1,5,2,6,7\n1,0,2,3,1.5,8\n5,2,0,1,4,6\n2,3,1,0,2,9\n"
                   "6,1.5,4,2,0,3\n7,8,6,9,3,0\n");
  const test::CliResult r =
      test::run_cli("-q evaluate " + q(dir + "/m.csv") + " --out " + q(dir + "/out") + " --no-draw");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  find(r.out, R"(  mAP [01]\.\d{3}   NN [01]\.\d{3}   FT [01]\.\d{3}   ST [01]\.\d{3}   E [01]\.\d{3}   )"
              R"(DCG [01]\.\d{3}\n)");
}

TEST(ConsoleFigures, NoiseGivesGapsInMeanEdgeLengthsAndGeodesicsAsAShareOfTheDiameter) {
  const std::string dir = test::scratch_dir("console-figures-noise");
  ASSERT_EQ(test::run_cli("-q generate swissroll -o " + q(dir + "/roll.off")).exit_code, 0);
  const test::CliResult r =
      test::run_cli("noise " + q(dir + "/roll.off") + " -o " + q(dir + "/glued.off") + " --glue 1 --relax 3");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  expect_three_figures(
      find(r.out, "max gap " + kNumber + R"( \()" + kNumber + " × the mean edge length " + kNumber +
                      R"(\), min ratio )" + kNumber + ", geodesic diameter " + kNumber),
      "noise");
  expect_three_figures(find(r.out, "glued \\d+ - \\d+: euclidean " + kNumber + R"( \()" + kNumber +
                                       " × the mean edge length\\), geodesic " + kNumber + R"( \(ratio )" +
                                       kNumber + ", " + kNumber + "% of the diameter\\)"),
                       "noise");
}

TEST(ConsoleFigures, BenchIcpGivesMillisecondsAndDistancesWithTheirShareOfTheDiagonal) {
  const test::CliResult r = test::run_cli("-q bench icp --points 300 --repeats 1 --no-open3d");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  expect_three_figures(find(r.out, "CPU " + kNumber + " ms, wall " + kNumber + " ms \\(goal 20 ms"),
                       "bench icp");
  expect_three_figures(find(r.out, "% of B's bounding-box diagonal, " + kNumber + "\\)"), "bench icp");
  expect_three_figures(find(r.out, "rmse " + kNumber + R"( \()" + kNumber + R"(%\), hausdorff )" + kNumber +
                                       R"( \()" + kNumber + "%\\)"),
                       "bench icp");
  expect_three_figures(
      find(r.out, "per iteration \\(wall / CPU\\): ours " + kNumber + " / " + kNumber + " ms"), "bench icp");
}

}  // namespace console_figures_test
}  // namespace cshapes
