// One source for each limit (support/option_limits.h): the library's check, the CLI's help and the CLI's refusal
// all say the same limit, for every option that has one.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <sstream>
#include <string>
#include <vector>

#include "cshapes/canon/coulomb.h"
#include "cshapes/canon/metric_projection.h"
#include "cshapes/canon/smacof.h"
#include "cshapes/data/articulated.h"
#include "cshapes/support/error.h"
#include "cshapes/mesh/io.h"
#include "cshapes/mesh/knn_graph.h"
#include "cshapes/data/synthetic.h"
#include "cshapes/data/topological_noise.h"
#include "cshapes/matching/icp.h"
#include "tests/test_support.h"

namespace cshapes {
namespace option_limits_test {

TEST(OptionLimits, HoldsDescribesAndNamesTheOption) {
  const Limit iterations = integer_limit("coulomb-max-iterations", 0, 1e8);
  EXPECT_TRUE(iterations.holds(0));
  EXPECT_TRUE(iterations.holds(1e8));
  EXPECT_FALSE(iterations.holds(-1));
  EXPECT_FALSE(iterations.holds(1e8 + 1));
  EXPECT_FALSE(iterations.holds(2.5));
  EXPECT_FALSE(iterations.holds(std::nan("")));
  EXPECT_EQ(iterations.describe(), "an integer 0..100000000");
  const Limit step = number_limit("step-factor", 0, kNoLimit, true);
  EXPECT_FALSE(step.holds(0));
  EXPECT_TRUE(step.holds(1e-300));
  EXPECT_EQ(step.describe(), "a number > 0");
  const Limit fraction = number_limit("tear-fraction", 0, 0.99);
  EXPECT_EQ(fraction.describe(), "a number in [0, 0.99]");
  EXPECT_EQ(number_limit("x", 1e-12, 1, false, true).brief(), "in [1e-12, 1)");
  try {
    check_limit(iterations, -5, "coulomb");
    FAIL() << "no error";
  } catch (const Error& e) {
    EXPECT_EQ(std::string(e.what()),
              "coulomb: coulomb-max-iterations must be an integer 0..100000000, got -5");
  }
}

// A value just outside the limit (below its minimum, or above its maximum when the minimum is -inf).
double outside(const Limit& limit) {
  if (limit.minimum_open) return limit.minimum;
  return limit.minimum - (limit.kind == Limit::Integer ? 1 : std::max(1e-3, std::abs(limit.minimum)));
}
double above(const Limit& limit) {
  return limit.kind == Limit::Integer ? limit.maximum + 1 : limit.maximum * 1.5 + 1e-3;
}

TEST(OptionLimits, TheLibraryTheHelpAndTheCliRefusalSayTheSameLimit) {
  const std::string dir = test::scratch_dir("option-limits");
  const std::string mesh = dir + "/ball.off";
  write_mesh(mesh, icosphere(1, 1.0));
  const std::string q = "'" + mesh + "'";
  struct Case {
    std::string command;  // the command line before the option, with its inputs
    Limit limit;
  };
  using namespace coulomb_limits;
  const std::string canon = "canon " + q + " -o '" + dir + "/c.ply' --method coulomb";
  const std::string mds = "canon " + q + " -o '" + dir + "/c.ply' --method smacof";
  const std::string noise = "noise " + q + " -o '" + dir + "/n.off'";
  const std::vector<Case> cases = {
      {canon, kStepFactor},
      {canon + " --step-rule fixed", kFixedStep},
      {canon, kCoulombSteps},
      {canon, kTearFraction},
      {canon, kTearAfter},
      {canon, kTearTimes},
      {canon, kTearInterval},
      {canon, kMaxIterations},
      {canon, kWindow},
      {canon, kTolerance},
      {canon, kMomentum},
      {canon, kAccuracy},
      {canon, kFmmRebuildEvery},
      {canon, kKnnLimit},
      {canon, projection_limits::kSteps},
      {canon + " --projection l1", projection_limits::kL1Floor},
      {canon, projection_limits::kDilation},
      {mds, smacof_limits::kIterations},
      {mds, smacof_limits::kTolerance},
      {mds + " --accelerate rre", smacof_limits::kWindow},
      {noise, noise_limits::kGlue},
      {noise, noise_limits::kMaxGap},
      {noise, noise_limits::kGapEdges},
      {noise, noise_limits::kMinRatio},
      {noise, noise_limits::kMinFraction},
      {noise, noise_limits::kSeparation},
      {noise, noise_limits::kRelax},
      {"align " + q + " " + q, icp_limits::kTrim},
      {"align " + q + " " + q, icp_limits::kTolerance},
      {"generate articulated --out '" + dir + "/a'", generate_limits::kPoses},
      {"generate articulated --out '" + dir + "/a'", generate_limits::kAmplitude},
      {"generate articulated --out '" + dir + "/a'", generate_limits::kVertices},
      {"generate dataset --out '" + dir + "/d'", generate_limits::kClasses},
      {"generate dataset --out '" + dir + "/d'", generate_limits::kNoisy},
      {"generate dataset --out '" + dir + "/d'", generate_limits::kGlue},
  };
  for (const Case& c : cases) {
    const std::string option = std::string("--") + c.limit.option;
    SCOPED_TRACE(c.command + " " + option);
    // The help shows the limit on the option's line.
    const size_t first_space = c.command.find(' ');
    const std::string help_command = c.command.substr(
        0, c.command.rfind("generate", 0) == 0 ? c.command.find(' ', first_space + 1) : first_space);
    // --help-all: Coulomb's single settings are listed there (the short help shows its preset).
    const test::CliResult help = test::run_cli(help_command + " --help-all");
    std::string line;  // the help's line that starts with the option
    std::istringstream lines(help.out);
    for (std::string l; std::getline(lines, l);)
      if (l.find_first_not_of(' ') != std::string::npos &&
          l.compare(l.find_first_not_of(' '), option.size() + 1, option + " ") == 0)
        line = l;
    ASSERT_FALSE(line.empty()) << help.out;
    EXPECT_NE(line.find(c.limit.brief()), std::string::npos) << line;
    // The CLI refuses a value outside in the limit's words, before any work (exit 2, the usage code).
    for (const double bad : {outside(c.limit), above(c.limit)}) {
      if (!std::isfinite(bad)) continue;
      std::string text = format_limit_number(bad);
      const test::CliResult r = test::run_cli(c.command + " " + option + " " + text);
      EXPECT_EQ(r.exit_code, 2) << r.err;
      EXPECT_NE(r.err.find(option), std::string::npos) << r.err;
      EXPECT_NE(r.err.find("expected " + c.limit.describe()), std::string::npos) << r.err;
      // And the library refuses it too, naming the same option.
      try {
        check_limit(c.limit, bad, "library");
        ADD_FAILURE() << "the library accepted " << text;
      } catch (const Error& e) {
        EXPECT_NE(std::string(e.what()).find(c.limit.option), std::string::npos) << e.what();
      }
    }
    // A value inside passes the library's check (the limit is not empty).
    EXPECT_TRUE(c.limit.holds(c.limit.minimum_open ? c.limit.minimum + 1 : c.limit.minimum));
  }
  std::filesystem::remove_all(dir);
}

}  // namespace option_limits_test
}  // namespace cshapes
