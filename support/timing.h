// Clocks for the timings cshapes reports, and the one median rule of every "median of repeats".
//
// Wall time is the monotonic std::chrono::steady_clock (never the calendar clock, which may jump).
// CPU time is CLOCK_PROCESS_CPUTIME_ID: the CPU seconds of all threads of the process, so when other jobs
// share the cores it shows the work done independently of the share obtained (with t threads
// busy it runs up to t times faster than wall time). Reading it is a system call (~0.1-0.5 µs); read the wall
// clock alone (WallClock::now, seconds_since) inside loops that run per task.
//
// Include this header from .cpp files only: several files outside the library define helpers of the same
// names for themselves.
#pragma once

#include <chrono>
#include <string>

#include "cshapes/support/stage_time.h"
#include <vector>

namespace cshapes {

using WallClock = std::chrono::steady_clock;

// Wall seconds from `start` to now.
double seconds_since(WallClock::time_point start);

// CPU seconds used so far by all threads of this process (origin arbitrary: use differences).
double process_cpu_seconds();

// CPU seconds used so far by the calling thread (origin arbitrary: use differences).
double thread_cpu_seconds();

// CPU seconds used so far by the child processes this process started and waited for (methods from
// outside, the figures' Python), their children included (origin arbitrary: use differences).
double children_cpu_seconds();

// Wall and process CPU time since construction (or the last restart()).
class Stopwatch {
 public:
  Stopwatch() { restart(); }
  void restart();
  double wall_seconds() const { return seconds_since(wall_start_); }
  double cpu_seconds() const { return process_cpu_seconds() - cpu_start_; }
  // The CPU seconds of the child processes waited for meanwhile.
  double children_cpu_seconds() const { return cshapes::children_cpu_seconds() - children_start_; }

 private:
  WallClock::time_point wall_start_;
  double cpu_start_ = 0, children_start_ = 0;
};

// The stage measured by `watch` since its start.
StageTime stage_time(std::string stage, std::string method, const Stopwatch& watch);

// The median of repeated measurements, by one rule: the upper median, i.e. the ⌊n/2⌋-th smallest value
// (0-based). For an odd count the middle value; for an even count the larger of the two middle values, not
// their mean, so the result is always one of the measurements. 0 for an empty vector. O(n) (nth_element).
// The paper experiment's Table 1 and every `cshapes bench` command report medians by this rule.
double median(std::vector<double> values);

}  // namespace cshapes
