// support/threads.h: the thread count chosen again between blocks of work (refresh_threads).
#include <gtest/gtest.h>
#include <omp.h>

#include <algorithm>
#include <cstdlib>

#include "cshapes/support/threads.h"

namespace cshapes {
namespace threads_test {

// With CSHAPES_EXACT_THREADS set the load is not read, so the choice is the request capped at 4 per core.
TEST(Threads, RefreshChoosesTheRequestedCountAgainAndSetsIt) {
  setenv("CSHAPES_EXACT_THREADS", "1", 1);
  const int before = omp_get_max_threads();
  const int cores = omp_get_num_procs();
  set_thread_request(3);
  omp_set_num_threads(1);  // as if an earlier block had been lowered to one thread
  EXPECT_EQ(refresh_threads(), std::min(3, 4 * cores));
  EXPECT_EQ(omp_get_max_threads(), std::min(3, 4 * cores));
  set_thread_request(1000 * cores);  // above 4 per core: capped
  EXPECT_EQ(refresh_threads(), 4 * cores);
  omp_set_num_threads(before);
  unsetenv("CSHAPES_EXACT_THREADS");
}

TEST(Threads, WithoutARequestRefreshChangesNothing) {
  const int before = omp_get_max_threads();
  set_thread_request(-1);
  omp_set_num_threads(1);
  EXPECT_EQ(refresh_threads(), 1);
  EXPECT_EQ(omp_get_max_threads(), 1);
  omp_set_num_threads(before);
}

TEST(Threads, RefreshInsideAParallelRegionChangesNothing) {
  setenv("CSHAPES_EXACT_THREADS", "1", 1);
  set_thread_request(2);
  int inside = -1;
#pragma omp parallel num_threads(2)
  {
#pragma omp single
    {
      const int outer = omp_get_max_threads();
      inside = refresh_threads() == outer;
    }
  }
  EXPECT_EQ(inside, 1);
  unsetenv("CSHAPES_EXACT_THREADS");
}

// The load lowers the count: with every core reported busy, at most the request and at least one thread.
TEST(Threads, TheCountFollowsTheLoadWithinItsBounds) {
  unsetenv("CSHAPES_EXACT_THREADS");
  set_thread_request(2);
  const int threads = refresh_threads();
  EXPECT_GE(threads, 1);
  EXPECT_LE(threads, 2);
  EXPECT_EQ(omp_get_max_threads(), threads);
}

}  // namespace threads_test
}  // namespace cshapes
