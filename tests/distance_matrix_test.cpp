// The memory check before n×n work (support/distance_matrix.h require_memory).
#include "cshapes/support/distance_matrix.h"

#include <gtest/gtest.h>
#include <sys/resource.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <string>

#include "cshapes/support/error.h"
#include "tests/test_support.h"

namespace cshapes {
namespace distance_matrix_test {

// The process's mapped bytes now (/proc/self/statm).
double mapped_bytes() {
  std::ifstream statm("/proc/self/statm");
  double pages = 0;
  statm >> pages;
  return pages * static_cast<double>(::sysconf(_SC_PAGESIZE));
}

TEST(RequireMemory, TheProcessAddressSpaceLimitCounts) {
  // Issue 22: only MemAvailable was read, so under `ulimit -v` the check passed and the run ended in a bare
  // "out of memory".
  struct rlimit before {};
  ASSERT_EQ(::getrlimit(RLIMIT_AS, &before), 0);
  const double room = 256e6;
  struct rlimit tight = before;
  tight.rlim_cur = static_cast<rlim_t>(mapped_bytes() + room);
  if (before.rlim_max != RLIM_INFINITY && tight.rlim_cur > before.rlim_max)
    GTEST_SKIP() << "hard limit too low";
  ASSERT_EQ(::setrlimit(RLIMIT_AS, &tight), 0);
  std::string message;
  try {
    require_memory(2e9, "a 2 GB matrix");
  } catch (const Error& e) {
    message = e.what();
  }
  ASSERT_EQ(::setrlimit(RLIMIT_AS, &before), 0);
  EXPECT_EQ(message.rfind("a 2 GB matrix needs 2 GB", 0), 0u) << message;
  EXPECT_NE(message.find("ulimit -v"), std::string::npos) << message;
  EXPECT_NO_THROW(require_memory(1e6, "a small matrix"));
}

TEST(RequireMemory, TheControlGroupLimitCounts) {
  // Issue 22: under a cgroup limit the check passed (only MemAvailable was read). A fake /proc/self/cgroup
  // and cgroup tree: the group's own limit less its use, a lower limit on a parent group, v1 and v2, "max".
  const std::string dir = test::scratch_dir("cgroup");
  auto put = [&](const std::string& file, const std::string& text) {
    std::filesystem::create_directories(std::filesystem::path(dir + file).parent_path());
    test::write_text(dir + file, text);
  };
  put("/v2/proc", "0::/jobs/run\n");
  put("/v2/root/jobs/run/memory.max", "1000000000\n");
  put("/v2/root/jobs/run/memory.current", "400000000\n");
  put("/v2/root/jobs/memory.max", "max\n");
  std::string rule;
  EXPECT_DOUBLE_EQ(control_group_memory_room(dir + "/v2/proc", dir + "/v2/root", &rule), 6e8);
  EXPECT_EQ(rule,
            "is available under the control group's memory limit (" + dir + "/v2/root/jobs/run/memory.max)");
  put("/v2/root/jobs/memory.max", "500000000\n");  // the parent's limit is lower, its use unknown
  EXPECT_DOUBLE_EQ(control_group_memory_room(dir + "/v2/proc", dir + "/v2/root", &rule), 5e8);
  EXPECT_NE(rule.find("/v2/root/jobs/memory.max"), std::string::npos) << rule;
  put("/v1/proc", "9:cpu:/x\n4:memory:/a/b\n0::/\n");
  put("/v1/root/memory/a/b/memory.limit_in_bytes", "2000000000\n");
  put("/v1/root/memory/a/b/memory.usage_in_bytes", "500000000\n");
  put("/v1/root/memory/memory.limit_in_bytes", "9223372036854771712\n");  // v1's "no limit"
  EXPECT_DOUBLE_EQ(control_group_memory_room(dir + "/v1/proc", dir + "/v1/root", &rule), 1.5e9);
  put("/none/proc", "0::/\n");
  put("/none/root/memory.max", "max\n");
  EXPECT_LT(control_group_memory_room(dir + "/none/proc", dir + "/none/root"), 0);
  std::filesystem::remove_all(dir);
}

TEST(RequireMemory, AskingForMoreThanTheMachineHasIsRefused) {
  try {
    require_memory(1e18, "an exabyte");
    ADD_FAILURE() << "accepted";
  } catch (const Error& e) {
    EXPECT_EQ(std::string(e.what()).rfind("an exabyte needs 1e+09 GB", 0), 0u) << e.what();
  }
}

// Above 2 MiB the matrix is advised for huge pages (uninitialized_distance_matrix): the advice must change
// nothing a caller sees, neither for a new matrix nor for one read from a file.
TEST(DistanceMatrixFile, AMatrixLargerThanAHugePageRoundTrips) {
  const Index n = 1100;  // 4.8 MB
  DistanceMatrix D = uninitialized_distance_matrix(n, n);
  ASSERT_EQ(D.rows(), n);
  ASSERT_EQ(D.cols(), n);
  for (Index j = 0; j < n; ++j)  // symmetric, as the file format requires
    for (Index i = 0; i < n; ++i) D(i, j) = static_cast<float>(i + j) + 1e-3f * static_cast<float>(i * j % 7);
  const std::string path = test::scratch_dir("huge_page_roundtrip") + "/D.bin";
  write_distance_matrix(path, D);
  const DistanceMatrix back = read_distance_matrix(path);
  std::filesystem::remove(path);
  ASSERT_EQ(back.rows(), n);
  EXPECT_TRUE(back == D) << "largest difference " << (back - D).cwiseAbs().maxCoeff();
  EXPECT_EQ(back(3, 1000), 1003 + 1e-3f * 4);
}

// A header's n is checked before it sizes anything: n = -600 (2^64 - 600 unsigned) in a file of the size
// 600² floats would take ended in an unnamed "out of memory"; now a named error.
TEST(DistanceMatrixFile, ANegativeOrHugeHeaderCountIsANamedError) {
  const std::string dir = test::scratch_dir("distance-matrix-header");
  for (const int64_t n : {int64_t{-600}, int64_t{1} << 40}) {
    SCOPED_TRACE(n);
    const std::string path = dir + "/bad.bin";
    {
      std::ofstream out(path, std::ios::binary);
      out.write("CSHDIST1", 8);
      out.write(reinterpret_cast<const char*>(&n), 8);
      const std::string body(4 * 600 * 600, '\0');
      out.write(body.data(), static_cast<std::streamsize>(body.size()));
    }
    try {
      read_distance_matrix(path);
      ADD_FAILURE() << "accepted";
    } catch (const Error& e) {
      const std::string message = e.what();
      EXPECT_EQ(message.rfind(path + ": header says n = ", 0), 0u) << message;
      EXPECT_NE(message.find(std::to_string(n)), std::string::npos) << message;
    }
  }
  std::filesystem::remove_all(dir);
}

}  // namespace distance_matrix_test
}  // namespace cshapes
