// The memory check before n×n work (core/distance_matrix.h require_memory).
#include "core/distance_matrix.h"

#include <gtest/gtest.h>
#include <sys/resource.h>
#include <unistd.h>

#include <fstream>
#include <string>

#include "core/error.h"

namespace cshapes {
namespace {

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

TEST(RequireMemory, AskingForMoreThanTheMachineHasIsRefused) {
  try {
    require_memory(1e18, "an exabyte");
    ADD_FAILURE() << "accepted";
  } catch (const Error& e) {
    EXPECT_EQ(std::string(e.what()).rfind("an exabyte needs 1e+09 GB", 0), 0u) << e.what();
  }
}

}  // namespace
}  // namespace cshapes
