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
      {"bench coulomb --n -5", "--n"},
      {"bench coulomb --n 1000000000000", "--n"},
      {"bench coulomb --order -1", "--order"},
      {"bench coulomb --theta -0.5", "--theta"},
      {"bench coulomb --leaf-size -3", "--leaf-size"},
      {"bench coulomb --accuracy 0", "--accuracy"},
      {"bench coulomb-iteration --n 3", "--n"},
      {"bench form --n -1", "--n"},
      {"bench form --repeats 0", "--repeats"},
      {"bench geodesics --n 2", "--n"},
      {"bench smacof --n -600", "--n"},
      {"bench smacof --iters 0", "--iters"},
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
  const test::CliResult r = test::run_cli("bench coulomb --n 300 --repeats 1");
  EXPECT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.err.find("kernels: "), std::string::npos) << r.err;
  const test::CliResult bad = test::run_cli("--version");
  EXPECT_EQ(bad.exit_code, 0);
  EXPECT_NE(bad.out.find("kernels: "), std::string::npos) << bad.out;
  const test::CliResult json = test::run_cli("bench coulomb --n 300 --repeats 1 --json");
  EXPECT_NE(json.out.find("\"simd\""), std::string::npos) << json.out;
  setenv("CSHAPES_SIMD", "sse9", 1);
  const test::CliResult unknown = test::run_cli("bench coulomb --n 300 --repeats 1 --json");
  unsetenv("CSHAPES_SIMD");
  EXPECT_EQ(unknown.exit_code, 2) << unknown.err;
  EXPECT_NE(unknown.err.find("CSHAPES_SIMD=sse9"), std::string::npos) << unknown.err;
  EXPECT_TRUE(unknown.out.empty()) << unknown.out;
}

}  // namespace bench_cli_test
}  // namespace cshapes
