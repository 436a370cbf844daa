#include "cshapes/support/timing.h"

#include <sys/resource.h>
#include <time.h>

#include <algorithm>
#include <utility>

namespace cshapes {

namespace {
double clock_seconds(clockid_t clock) {
  timespec t{};
  clock_gettime(clock, &t);
  return static_cast<double>(t.tv_sec) + 1e-9 * static_cast<double>(t.tv_nsec);
}
}  // namespace

double seconds_since(WallClock::time_point start) {
  return std::chrono::duration<double>(WallClock::now() - start).count();
}

double process_cpu_seconds() {
  return clock_seconds(CLOCK_PROCESS_CPUTIME_ID);
}

double thread_cpu_seconds() {
  return clock_seconds(CLOCK_THREAD_CPUTIME_ID);
}

double children_cpu_seconds() {
  rusage usage{};
  getrusage(RUSAGE_CHILDREN, &usage);
  auto seconds = [](const timeval& t) { return static_cast<double>(t.tv_sec) + 1e-6 * static_cast<double>(t.tv_usec); };
  return seconds(usage.ru_utime) + seconds(usage.ru_stime);
}

void Stopwatch::restart() {
  cpu_start_ = process_cpu_seconds();
  children_start_ = children_cpu_seconds();
  wall_start_ = WallClock::now();
}

StageTime stage_time(std::string stage, std::string method, const Stopwatch& watch) {
  return {std::move(stage), std::move(method), watch.wall_seconds(),
          watch.cpu_seconds() + watch.children_cpu_seconds()};
}

double median(std::vector<double> values) {
  if (values.empty()) return 0;
  const auto middle = values.begin() + static_cast<std::ptrdiff_t>(values.size() / 2);
  std::nth_element(values.begin(), middle, values.end());
  return *middle;
}

}  // namespace cshapes
