// The CLI in logs: progress written into a file or a pipe is plain lines (no "\r" fragments, no estimate in
// the first seconds of a stage), and a warning carries one prefix ("cshapes <command>: warning: …"), also
// under --quiet — including the library's warnings said on the note channel.
#include <gtest/gtest.h>

#include <string>

#include "core/io.h"
#include "core/synthetic.h"
#include "test_support.h"

namespace cshapes {
namespace {

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

}  // namespace
}  // namespace cshapes
