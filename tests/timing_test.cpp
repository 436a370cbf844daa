#include "cshapes/support/timing.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>

namespace cshapes {
namespace timing_test {

TEST(Median, UpperMedianKnownAnswers) {
  EXPECT_EQ(median({}), 0.0);
  EXPECT_EQ(median({3.5}), 3.5);
  EXPECT_EQ(median({5, 1, 3}), 3.0);
  // An even count: the larger of the two middle values, never their mean.
  EXPECT_EQ(median({4, 1, 3, 2}), 3.0);
  EXPECT_EQ(median({1, 2}), 2.0);
  EXPECT_EQ(median({2, 2, 1, 1}), 2.0);
  EXPECT_EQ(median({-1, -5, -3, -4}), -3.0);
}

// Invariants: independent of the input order, always one of the values, at least half of the values at or
// below it and at least half at or above it (the upper one for an even count).
TEST(Median, OrderInvariantAndOneOfTheValues) {
  std::mt19937_64 rng(5);
  std::uniform_real_distribution<double> u(-10, 10);
  for (int n = 1; n <= 40; ++n) {
    std::vector<double> v(static_cast<size_t>(n));
    for (double& x : v) x = u(rng);
    const double m = median(v);
    EXPECT_NE(std::find(v.begin(), v.end(), m), v.end());
    const long below = std::count_if(v.begin(), v.end(), [&](double x) { return x < m; });
    EXPECT_EQ(below, n / 2) << "n " << n;
    std::shuffle(v.begin(), v.end(), rng);
    EXPECT_EQ(median(v), m);
    // Brute force: sort and index.
    std::sort(v.begin(), v.end());
    EXPECT_EQ(m, v[static_cast<size_t>(n / 2)]);
  }
}

// The clocks run forward and the CPU clock counts this thread's work (no assertion on how fast anything is).
TEST(Stopwatch, ClocksAdvanceAndRestart) {
  Stopwatch watch;
  EXPECT_GE(watch.wall_seconds(), 0.0);
  EXPECT_GE(watch.cpu_seconds(), 0.0);
  const double thread_start = thread_cpu_seconds();
  volatile double sink = 0;
  while (thread_cpu_seconds() - thread_start < 0.02)
    for (int k = 0; k < 10000; ++k) sink = sink + std::sqrt(static_cast<double>(k));
  const double cpu = watch.cpu_seconds(), wall = watch.wall_seconds();
  EXPECT_GE(cpu, 0.02 * 0.999);   // the process clock includes this thread's 20 ms
  EXPECT_GE(wall, 0.02 * 0.999);  // one busy thread cannot use more CPU time than wall time passes
  EXPECT_GE(watch.wall_seconds(), wall);
  watch.restart();
  EXPECT_LT(watch.wall_seconds(), wall);
  EXPECT_LT(watch.cpu_seconds(), cpu);
  const WallClock::time_point start = WallClock::now();
  EXPECT_GE(seconds_since(start), 0.0);
  EXPECT_GT(process_cpu_seconds(), 0.0);
}

}  // namespace timing_test
}  // namespace cshapes
