// `cshapes bench …`: a bad option is a usage error (exit 2) named by the parser before any work, never a
// library error (exit 1) or a raw container message; every bench says its kernels (support/simd.h).
#include <gtest/gtest.h>

#include <cstdlib>
#include <string>
#include <vector>

#include "test_support.h"

namespace cshapes {
namespace bench_cli_test {

TEST(BenchCli, OutOfRangeOptionsAreUsageErrorsNamingTheOption) {
  const std::vector<std::pair<std::string, std::string>> cases = {
      {"bench coulomb --points -5", "--points"},
      {"bench coulomb --points 1000000000000", "--points"},
      {"bench coulomb --order -1", "--order"},
      {"bench coulomb --theta -0.5", "--theta"},
      {"bench coulomb --leaf-size -3", "--leaf-size"},
      {"bench coulomb --accuracy 0", "--accuracy"},
      {"bench coulomb-iteration --vertices 3", "--vertices"},
      {"bench form --vertices -1", "--vertices"},
      {"bench form --repeats 0", "--repeats"},
      {"bench geodesics --vertices 2", "--vertices"},
      {"bench smacof --points -600", "--points"},
      {"bench smacof --iterations 0", "--iterations"},
      {"bench smacof --smacof-max-iterations -1", "--smacof-max-iterations"},
      {"bench smacof --smacof-window 1", "--smacof-window"},
  };
  for (const auto& [arguments, option] : cases) {
    const test::CliResult r = test::run_cli(arguments);
    EXPECT_EQ(r.exit_code, 2) << arguments << ": " << r.err;
    EXPECT_NE(r.err.find(option), std::string::npos) << arguments << ": " << r.err;
    EXPECT_EQ(r.err.find("_M_default_append"), std::string::npos) << arguments << ": " << r.err;
    EXPECT_TRUE(r.out.empty()) << arguments << ": " << r.out;
  }
}

TEST(BenchCli, EveryBenchSaysItsKernelsAndAnUnknownInstructionSetIsRefused) {
  const test::CliResult r = test::run_cli("bench coulomb --points 300 --repeats 1");
  EXPECT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.err.find("kernels: "), std::string::npos) << r.err;
  const test::CliResult bad = test::run_cli("--version");
  EXPECT_EQ(bad.exit_code, 0);
  EXPECT_NE(bad.out.find("kernels: "), std::string::npos) << bad.out;
  const test::CliResult json = test::run_cli("bench coulomb --points 300 --repeats 1 --json");
  EXPECT_NE(json.out.find("\"simd\""), std::string::npos) << json.out;
  setenv("CSHAPES_SIMD", "sse9", 1);
  const test::CliResult unknown = test::run_cli("bench coulomb --points 300 --repeats 1 --json");
  unsetenv("CSHAPES_SIMD");
  EXPECT_EQ(unknown.exit_code, 2) << unknown.err;
  EXPECT_NE(unknown.err.find("CSHAPES_SIMD=sse9"), std::string::npos) << unknown.err;
  EXPECT_TRUE(unknown.out.empty()) << unknown.out;
}

}  // namespace bench_cli_test
}  // namespace cshapes
